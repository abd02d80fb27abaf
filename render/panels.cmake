# plastivox_panels: the Fig. 5 bar-chart panels from stats.json, as SVG text and as PNG drawn
# with Dear ImGui in plastivox_render's OSMesa context (one layout drives both).
add_library(plastivox_panels STATIC
  ${CMAKE_CURRENT_LIST_DIR}/src/panel_stats.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/panel_layout.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/panel_svg.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/panel_png.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/panel_figures.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/battery_heat_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/archive_map.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/qd_curve.cpp
)
target_include_directories(plastivox_panels PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(plastivox_panels PUBLIC plastivox_render nlohmann_json::nlohmann_json
                      PRIVATE plastivox_io)
