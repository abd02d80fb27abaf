// MP4 video writer and reader, in-process with FFmpeg's libraries (libavcodec, libavformat,
// libswscale). Frames go in as RGBA rows, top row first; the file comes out as H.264 (libx264)
// in MP4, or MPEG-4 Part 2 in MP4 where libx264 is missing. Output bytes are deterministic: the
// same frames and options give the same file on every run (fixed encoder threads and parameters,
// bit-exact colour conversion, no creation time, no version strings from libavformat).
//
// The container follows the path's extension: .mp4 or .m4v (MP4), .mkv (Matroska); any other
// extension is refused with that list.
// The file is written to a temporary name beside the final path ("<path>.tmp.<pid>") and renamed
// into place by finish(); a writer destroyed before finish() removes the temporary, so a final
// name never holds half a video, and a new writer removes temporaries of the same path whose
// process is gone (a killed run). Errors are VideoError with one line naming the path.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/base/error.hpp"

namespace plastivox::render {

// Any failure of the writer or reader: one line, naming the file.
class VideoError : public Error {
 public:
  using Error::Error;
};

struct VideoOptions {
  int width = 0;               // frame width, pixels (1..8192); an odd size is padded, see below
  int height = 0;              // frame height, pixels (1..8192)
  double fps = 30;             // frames per second (0 < fps <= 1000); stored as an exact fraction
  std::string codec = "auto";  // "auto" (best available), "h264" (libx264) or "mpeg4"
  int quality = 20;            // constant quality: x264 CRF (0 lossless .. 51); mpeg4 maps it to q
  int threads = 1;             // encoder threads; fixed (never "auto") so bytes do not depend on
                               // the machine. 1 is the reproducible default; 2+ is faster.
};

// Streams frames into an MP4 file. Not thread-safe; one writer per file.
// 4:2:0 chroma needs even sizes: an odd width or height is padded by one column/row that repeats
// the last one, so the video is (width+1)x(height) etc.; encoded_width()/height() say so.
class VideoWriter {
 public:
  // Opens the encoder and the temporary file. Throws VideoError on a bad size, fps, unknown or
  // unavailable codec, or an unwritable path.
  VideoWriter(const std::string& path, const VideoOptions& options);
  ~VideoWriter();  // removes the temporary file if finish() was not reached
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Encodes one frame: 4*width*height bytes, RGBA, rows top to bottom, alpha ignored.
  void add_frame(const uint8_t* rgba_top_down);
  // Flushes the encoder, writes the trailer, closes and renames into place. Call once.
  void finish();

  std::string codec_name() const;  // "h264" or "mpeg4": the codec actually used
  int encoded_width() const;       // width rounded up to even
  int encoded_height() const;      // height rounded up to even
  int frames() const;              // frames added so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Throws VideoError naming path when its extension names no container this writer makes
// (the writer's own check, callable before a life is simulated for it).
void check_video_name(const std::string& path);

// The codecs this build can write, best first (a subset of {"h264", "mpeg4"}).
std::vector<std::string> available_video_codecs();

struct VideoInfo {
  int width = 0, height = 0;  // coded picture size, pixels
  int frames = 0;             // frames decoded (every frame is decoded to count them)
  double duration_s = 0;      // container duration, seconds
  std::string codec;          // codec name as libavcodec says, e.g. "h264", "mpeg4"
  double fps = 0;             // average frame rate of the video stream
};

// Opens a video file and decodes every frame of its first video stream. Throws VideoError.
VideoInfo probe_video(const std::string& path);

// One decoded frame as RGBA (top row first), for tests and checks: frame `index` (0-based) of
// the first video stream, converted with the stream's colour matrix. Throws VideoError if the
// file has fewer frames.
struct DecodedFrame {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 4*width*height bytes
};
DecodedFrame read_video_frame(const std::string& path, int index);

}  // namespace plastivox::render
