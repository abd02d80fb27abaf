# plastivox_video: MP4 writer and reader in-process with FFmpeg's libraries
# (Debian: libavcodec-dev libavformat-dev libswscale-dev libavutil-dev; libx264 for H.264).
find_package(PkgConfig REQUIRED)
pkg_check_modules(FFMPEG REQUIRED IMPORTED_TARGET libavcodec libavformat libswscale libavutil)
add_library(plastivox_video STATIC
  ${CMAKE_CURRENT_LIST_DIR}/src/video_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/video_reader.cpp
)
target_include_directories(plastivox_video PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include
                                           PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src)
target_link_libraries(plastivox_video PUBLIC plastivox_base PRIVATE PkgConfig::FFMPEG)
