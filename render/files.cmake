# plastivox_render_files: lives read from robot (.json, .vxa), results and recorded-life (.h5)
# files, and the rendering commands that take file names (plastivox/render/files.hpp). A library
# of its own, in render/files/, over plastivox_render: it compiles and simulates lives and links
# the evolver (a results file's champion is decoded by evo), which plastivox_render (render/src,
# render/include) never does (the test Layers.RenderNeverSimulates). The program, the Python
# module, the tests and the benchmarks use it.
add_library(plastivox_render_files ${CMAKE_CURRENT_LIST_DIR}/files/files.cpp
                                  ${CMAKE_CURRENT_LIST_DIR}/files/archive_files.cpp)
target_include_directories(plastivox_render_files PUBLIC ${CMAKE_CURRENT_LIST_DIR}/files/include)
target_link_libraries(plastivox_render_files PUBLIC plastivox_render plastivox_panels
                      PRIVATE plastivox_evo)
