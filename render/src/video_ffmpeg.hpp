// Internals shared by the video writer and reader: FFmpeg error text and owning handles.
#pragma once

#include <string>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libswscale/swscale.h>
}

#include "plastivox/render/video_writer.hpp"

namespace plastivox::render::video_detail {

// "what: FFmpeg's message for err".
inline std::string av_error(const std::string& what, int err) {
  char buf[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(err, buf, sizeof buf);
  return what + ": " + buf;
}

// Deleters so FFmpeg objects live in std::unique_ptr and are released on every path.
struct CodecContextFree {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameFree {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketFree {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct SwsFree {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};

}  // namespace plastivox::render::video_detail
