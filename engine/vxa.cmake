# VXA (Voxelyze/VoxCAD XML) import and export: a separate library so the core engine keeps
# no XML dependency. Included from engine/CMakeLists.txt.
find_package(tinyxml2 CONFIG QUIET)
if(TARGET tinyxml2::tinyxml2)
  set(PLASTIVOX_TINYXML2 tinyxml2::tinyxml2)
else()
  find_library(TINYXML2_LIB tinyxml2)
  find_path(TINYXML2_INCLUDE_DIR tinyxml2.h)
  if(NOT TINYXML2_LIB OR NOT TINYXML2_INCLUDE_DIR)
    message(FATAL_ERROR "tinyxml2 not found (Debian: apt-get install libtinyxml2-dev)")
  endif()
  add_library(plastivox_tinyxml2 INTERFACE)
  target_link_libraries(plastivox_tinyxml2 INTERFACE ${TINYXML2_LIB})
  target_include_directories(plastivox_tinyxml2 SYSTEM INTERFACE ${TINYXML2_INCLUDE_DIR})
  set(PLASTIVOX_TINYXML2 plastivox_tinyxml2)
endif()

add_library(plastivox_vxa
  ${CMAKE_CURRENT_LIST_DIR}/src/vxa_read.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/vxa_write.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/robot_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/voxcraft_read.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/voxcraft_write.cpp
)
target_include_directories(plastivox_vxa PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src)
target_link_libraries(plastivox_vxa PUBLIC plastivox_engine PRIVATE ${PLASTIVOX_TINYXML2})
