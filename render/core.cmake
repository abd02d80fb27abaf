# plastivox_render: off-screen OpenGL through OSMesa (Debian: libosmesa6-dev), Dear ImGui
# 1.86 (libimgui-dev: static library with the OpenGL 2 backend), PNG (libpng-dev), fonts
# (fonts-dejavu-core). libOSMesa exports every GL entry point itself, so nothing links libGL.
find_path(OSMESA_INCLUDE_DIR GL/osmesa.h REQUIRED)
find_library(OSMESA_LIBRARY NAMES OSMesa REQUIRED)
find_path(IMGUI_INCLUDE_DIR imgui.h PATH_SUFFIXES imgui REQUIRED)
find_library(IMGUI_LIBRARY NAMES libimgui.a imgui REQUIRED)
find_library(STB_LIBRARY NAMES stb REQUIRED)  # libstb-dev: stb_truetype, which ImGui's fonts use
find_package(PNG REQUIRED)

add_library(plastivox_render
  ${CMAKE_CURRENT_LIST_DIR}/src/assets.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/offscreen.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/png_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/colormap.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/color_scale.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/life.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/history_file.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/viewer_pack.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/base64.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/viewer_page.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/shown_life.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/report_lives.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/world_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/camera_path.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene_gl.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/overlay.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/render_life.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/gallery.cpp
)
target_include_directories(plastivox_render PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include
                           PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src)
# ImGui's headers are public (callers draw with ImDrawList); SYSTEM keeps their warnings out.
target_include_directories(plastivox_render SYSTEM PUBLIC ${IMGUI_INCLUDE_DIR}
                           PRIVATE ${OSMESA_INCLUDE_DIR})
# Drawing knows lives and frames only: reading them from robot, results and recorded-life
# files is plastivox_render_files' (render/files/, above render and the evolver).
target_link_libraries(plastivox_render PUBLIC plastivox_io
                      PRIVATE plastivox_video nlohmann_json::nlohmann_json ${IMGUI_LIBRARY}
                              ${STB_LIBRARY} ${OSMESA_LIBRARY} PNG::PNG)
target_link_libraries(plastivox_render PRIVATE ${CMAKE_DL_LIBS})  # dladdr1: where am I loaded from

# The data files read at run time (shaders, viewer scripts; the presets are also compiled in)
# are found relative to the program or module itself, in the nearest share/plastivox/assets
# above it (plastivox/render/assets.hpp), never at a path fixed when building: installed, in
# <prefix>/share/plastivox/assets; in the build tree, through a link to the source's assets/,
# so a build runs as it is, uncopied. $PLASTIVOX_ASSETS overrides both.
file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/share/plastivox)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/assets ${CMAKE_BINARY_DIR}/share/plastivox/assets SYMBOLIC)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets/ DESTINATION share/plastivox/assets)
