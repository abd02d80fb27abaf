// Reading videos back: probe_video (size, codec, duration, and a frame count by decoding every
// frame) and read_video_frame (one frame as RGBA). Used by tests and by callers that check what
// they wrote; single-threaded decoding, so it is slow for long 4K videos but exact.
#include <functional>
#include <memory>
#include <string>

#include "fp_guard.hpp"
#include "plastivox/render/video_writer.hpp"
#include "video_ffmpeg.hpp"

namespace plastivox::render {

using video_detail::av_error;

namespace {

// An opened input with the decoder of its first video stream.
class Decoder {
 public:
  explicit Decoder(const std::string& path) : path_(path) {
    int err = avformat_open_input(&format_, path.c_str(), nullptr, nullptr);
    if (err < 0) fail(av_error("cannot open video", err));
    err = avformat_find_stream_info(format_, nullptr);
    if (err < 0) fail(av_error("cannot read stream info", err));
    const AVCodec* dec = nullptr;
    stream_ = av_find_best_stream(format_, AVMEDIA_TYPE_VIDEO, -1, -1, &dec, 0);
    if (stream_ < 0 || !dec) fail("no decodable video stream");
    decoder_.reset(avcodec_alloc_context3(dec));
    if (!decoder_) fail("out of memory allocating the decoder");
    err = avcodec_parameters_to_context(decoder_.get(), format_->streams[stream_]->codecpar);
    if (err < 0) fail(av_error("bad codec parameters", err));
    decoder_->thread_count = 1;
    err = avcodec_open2(decoder_.get(), dec, nullptr);
    if (err < 0) fail(av_error("cannot open the decoder", err));
    packet_.reset(av_packet_alloc());
    frame_.reset(av_frame_alloc());
    if (!packet_ || !frame_) fail("out of memory allocating frames");
  }
  ~Decoder() { avformat_close_input(&format_); }
  Decoder(const Decoder&) = delete;
  Decoder& operator=(const Decoder&) = delete;

  [[noreturn]] void fail(const std::string& message) const {
    throw VideoError(path_ + ": " + message);
  }

  const AVFormatContext& format() const { return *format_; }
  const AVStream& stream() const { return *format_->streams[stream_]; }
  const AVCodecContext& decoder() const { return *decoder_; }

  // Calls visit(frame) for each decoded frame in display order until it returns false.
  void each_frame(const std::function<bool(const AVFrame&)>& visit) {
    bool more = true, draining = false;
    while (more) {
      if (!draining) {
        const int err = av_read_frame(format_, packet_.get());
        if (err == AVERROR_EOF) {
          draining = true;
          avcodec_send_packet(decoder_.get(), nullptr);
        } else if (err < 0) {
          fail(av_error("read error", err));
        } else {
          const bool ours = packet_->stream_index == stream_;
          const int serr = ours ? avcodec_send_packet(decoder_.get(), packet_.get()) : 0;
          av_packet_unref(packet_.get());
          if (serr < 0) fail(av_error("corrupt video data", serr));
        }
      }
      for (;;) {
        const int err = avcodec_receive_frame(decoder_.get(), frame_.get());
        if (err == AVERROR(EAGAIN)) break;
        if (err == AVERROR_EOF) return;
        if (err < 0) fail(av_error("decoding failed", err));
        more = visit(*frame_);
        av_frame_unref(frame_.get());
        if (!more) return;
      }
    }
  }

 private:
  std::string path_;
  AVFormatContext* format_ = nullptr;
  int stream_ = -1;
  std::unique_ptr<AVCodecContext, video_detail::CodecContextFree> decoder_;
  std::unique_ptr<AVPacket, video_detail::PacketFree> packet_;
  std::unique_ptr<AVFrame, video_detail::FrameFree> frame_;
};

}  // namespace

VideoInfo probe_video(const std::string& path) {
  const FpTrapsMasked masked;  // FFmpeg's SIMD code may compute with NaN; see fp_guard.hpp
  Decoder d(path);
  VideoInfo info;
  info.width = d.decoder().width;
  info.height = d.decoder().height;
  info.codec = avcodec_get_name(d.decoder().codec_id);
  const AVStream& s = d.stream();
  if (s.avg_frame_rate.num > 0 && s.avg_frame_rate.den > 0) info.fps = av_q2d(s.avg_frame_rate);
  if (d.format().duration != AV_NOPTS_VALUE) {
    info.duration_s = static_cast<double>(d.format().duration) / AV_TIME_BASE;
  } else if (s.duration != AV_NOPTS_VALUE) {
    info.duration_s = static_cast<double>(s.duration) * av_q2d(s.time_base);
  }
  d.each_frame([&](const AVFrame&) {
    ++info.frames;
    return true;
  });
  return info;
}

DecodedFrame read_video_frame(const std::string& path, int index) {
  const FpTrapsMasked masked;
  Decoder d(path);
  DecodedFrame out;
  int seen = 0;
  d.each_frame([&](const AVFrame& f) {
    if (seen++ < index) return true;
    out.width = f.width;
    out.height = f.height;
    out.rgba.resize(4 * static_cast<size_t>(f.width) * f.height);
    std::unique_ptr<SwsContext, video_detail::SwsFree> sws(sws_getContext(
        f.width, f.height, static_cast<AVPixelFormat>(f.format), f.width, f.height, AV_PIX_FMT_RGBA,
        SWS_BICUBIC | SWS_BITEXACT | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr,
        nullptr));
    if (!sws) d.fail("cannot set up the YUV to RGBA conversion");
    // The stream's own matrix and range (the writer tags BT.709, limited range).
    const int* yuv = sws_getCoefficients(f.colorspace);
    const int full = f.color_range == AVCOL_RANGE_JPEG ? 1 : 0;
    sws_setColorspaceDetails(sws.get(), yuv, full, sws_getCoefficients(SWS_CS_DEFAULT), 1, 0,
                             1 << 16, 1 << 16);
    uint8_t* planes[1] = {out.rgba.data()};
    const int strides[1] = {4 * f.width};
    sws_scale(sws.get(), f.data, f.linesize, 0, f.height, planes, strides);
    return false;
  });
  if (out.rgba.empty()) {
    d.fail("has " + std::to_string(seen) + " frames; frame " + std::to_string(index) +
           " was asked for");
  }
  return out;
}

}  // namespace plastivox::render
