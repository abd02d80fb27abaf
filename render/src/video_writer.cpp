// VideoWriter: RGBA frames -> (swscale, bit-exact) -> YUV 4:2:0 -> libx264 or mpeg4 -> MP4.
//
// Reproducibility is the design constraint. Everything that could make two runs differ is
// pinned: the encoder thread count is an option with a fixed default (never "auto", which would
// follow the machine's core count); x264 runs with its deterministic defaults; swscale runs with
// SWS_BITEXACT | SWS_ACCURATE_RND so its SIMD paths give the C path's bytes; libavformat and
// libavcodec get their BITEXACT flags, which drop creation times and version strings from the
// container. Timestamps are frame indices in a 1/fps time base, so durations are exact.
#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include "fp_guard.hpp"
#include "plastivox/render/video_writer.hpp"

#include "plastivox/base/output_path.hpp"
#include "video_ffmpeg.hpp"

extern "C" {
#include <libavutil/log.h>
#include <libavutil/rational.h>
}

namespace plastivox::render {

using video_detail::av_error;

namespace {

constexpr int kMaxSide = 8192;  // pixels; beyond every codec level we use

// FFmpeg logs encoder settings and muxer progress at "info" level on stderr; a command line tool
// should print one line on error and nothing otherwise. Lowered once, and only if the embedding
// program left the default level in place.
void quiet_ffmpeg_logs() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_ERROR);
  });
}

// The libavcodec encoder behind one of our codec names, or null if this build lacks it.
const AVCodec* find_encoder(const std::string& codec) {
  if (codec == "h264") return avcodec_find_encoder_by_name("libx264");
  if (codec == "mpeg4") return avcodec_find_encoder_by_name("mpeg4");
  return nullptr;
}

}  // namespace

std::vector<std::string> available_video_codecs() {
  std::vector<std::string> out;
  for (const char* name : {"h264", "mpeg4"}) {
    if (find_encoder(name)) out.push_back(name);
  }
  return out;
}

struct VideoWriter::Impl {
  std::string path, tmp;
  VideoOptions options;
  std::string codec;                  // our name of the codec in use
  int coded_w = 0, coded_h = 0;       // even sizes actually encoded
  AVFormatContext* format = nullptr;  // owns the AVIO context once opened
  AVStream* stream = nullptr;         // owned by format
  std::unique_ptr<AVCodecContext, video_detail::CodecContextFree> encoder;
  std::unique_ptr<AVFrame, video_detail::FrameFree> frame;
  std::unique_ptr<AVPacket, video_detail::PacketFree> packet;
  std::unique_ptr<SwsContext, video_detail::SwsFree> sws;
  std::vector<uint8_t> padded;  // RGBA, coded_w x coded_h, used only for odd input sizes
  int64_t next_pts = 0;
  bool finished = false;

  ~Impl() { close(); }

  // Releases FFmpeg objects; closes the file if still open.
  void close() {
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
      format = nullptr;
    }
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw VideoError(path + ": " + message);
  }

  void open_encoder();
  void open_file();
  void drain(bool flushing);
};

// The muxer for the path's extension: ".mp4" (and ".m4v") MP4, ".mkv" Matroska; both carry
// H.264 and MPEG-4 Part 2. Anything else (".avi", ".webm": WebM needs VP8/VP9/AV1, which this
// writer does not encode) is refused with the list.
const char* muxer_for(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".mp4" || ext == ".m4v") return "mp4";
  if (ext == ".mkv") return "matroska";
  return nullptr;
}

void VideoWriter::Impl::open_encoder() {
  const AVCodec* enc = find_encoder(codec);
  if (!enc) fail("video codec '" + codec + "' is not available in this FFmpeg build");
  encoder.reset(avcodec_alloc_context3(enc));
  if (!encoder) fail("out of memory allocating the encoder");
  AVCodecContext* c = encoder.get();
  const AVRational rate = av_d2q(options.fps, 1000000);
  c->width = coded_w;
  c->height = coded_h;
  c->pix_fmt = AV_PIX_FMT_YUV420P;
  c->time_base = av_inv_q(rate);
  c->framerate = rate;
  c->sample_aspect_ratio = AVRational{1, 1};
  c->gop_size = std::max(1, static_cast<int>(std::lround(options.fps * 2)));  // key frame / 2 s
  c->thread_count = options.threads;
  c->flags |= AV_CODEC_FLAG_BITEXACT;
  // Rendered frames are sRGB; tag the stream with the matrix swscale uses (BT.709, limited
  // range) so players convert back to the same colours.
  c->color_primaries = AVCOL_PRI_BT709;
  c->color_trc = AVCOL_TRC_BT709;
  c->colorspace = AVCOL_SPC_BT709;
  c->color_range = AVCOL_RANGE_MPEG;
  if (format->oformat->flags & AVFMT_GLOBALHEADER) c->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

  AVDictionary* opts = nullptr;
  if (codec == "h264") {
    av_dict_set(&opts, "preset", "medium", 0);
    av_dict_set_int(&opts, "crf", options.quality, 0);
    // Frame threads (not slices) so the stream is the same as a single-threaded one's in
    // structure; the thread count itself is fixed by options.threads. No MB-tree rate
    // control: x264 0.164's MB-tree reads memory it has not written, so its output followed
    // whatever the heap held before (same frames, different bytes once other work -- or
    // another thread -- had used that memory; see the heap test in video_writer_test).
    av_dict_set(&opts, "x264-params", "sliced-threads=0:mbtree=0", 0);
  } else {
    // MPEG-4 Part 2 at a constant quantiser q = quality/5 in 2..10: CRF 20 -> q 4, which
    // looks about as clean as x264 at CRF 20 (at several times the size).
    const int q = std::clamp(options.quality / 5, 2, 31);
    c->flags |= AV_CODEC_FLAG_QSCALE;
    c->global_quality = FF_QP2LAMBDA * q;
    c->max_b_frames = 0;
  }
  const int err = avcodec_open2(c, enc, &opts);
  av_dict_free(&opts);
  if (err < 0) fail(av_error("cannot open the " + codec + " encoder", err));

  frame.reset(av_frame_alloc());
  packet.reset(av_packet_alloc());
  if (!frame || !packet) fail("out of memory allocating frames");
  frame->format = c->pix_fmt;
  frame->width = coded_w;
  frame->height = coded_h;
  if (av_frame_get_buffer(frame.get(), 0) < 0) fail("out of memory allocating a frame");

  sws.reset(sws_getContext(coded_w, coded_h, AV_PIX_FMT_RGBA, coded_w, coded_h, AV_PIX_FMT_YUV420P,
                           SWS_BICUBIC | SWS_BITEXACT | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INP,
                           nullptr, nullptr, nullptr));
  if (!sws) fail("cannot set up the RGBA to YUV conversion");
  const int* rgb = sws_getCoefficients(SWS_CS_DEFAULT);
  const int* yuv = sws_getCoefficients(SWS_CS_ITU709);
  sws_setColorspaceDetails(sws.get(), rgb, 1, yuv, 0, 0, 1 << 16, 1 << 16);
}

void VideoWriter::Impl::open_file() {
  stream = avformat_new_stream(format, nullptr);
  if (!stream) fail("cannot add a video stream");
  stream->time_base = encoder->time_base;
  stream->avg_frame_rate = encoder->framerate;
  int err = avcodec_parameters_from_context(stream->codecpar, encoder.get());
  if (err < 0) fail(av_error("cannot copy codec parameters", err));

  err = avio_open(&format->pb, tmp.c_str(), AVIO_FLAG_WRITE);
  if (err < 0) fail(av_error("cannot write " + tmp, err));
  AVDictionary* opts = nullptr;
  av_dict_set(&opts, "movflags", "+faststart", 0);  // index first: plays while downloading
  err = avformat_write_header(format, &opts);
  av_dict_free(&opts);
  if (err < 0) fail(av_error("cannot write the MP4 header", err));
}

// Moves every packet the encoder has ready into the file.
void VideoWriter::Impl::drain(bool flushing) {
  for (;;) {
    const int err = avcodec_receive_packet(encoder.get(), packet.get());
    if (err == AVERROR(EAGAIN) || (flushing && err == AVERROR_EOF)) return;
    if (err < 0) fail(av_error("encoding failed", err));
    if (packet->duration == 0) packet->duration = 1;  // one frame, in the 1/fps time base
    av_packet_rescale_ts(packet.get(), encoder->time_base, stream->time_base);
    packet->stream_index = stream->index;
    const int werr = av_interleaved_write_frame(format, packet.get());  // takes the packet
    if (werr < 0) fail(av_error("cannot write to " + tmp, werr));
  }
}

VideoWriter::VideoWriter(const std::string& path, const VideoOptions& options)
    : impl_(std::make_unique<Impl>()) {
  const FpTrapsMasked masked;  // x264's assembly computes with NaN; see fp_guard.hpp
  quiet_ffmpeg_logs();
  Impl& m = *impl_;
  m.path = path;
  m.options = options;
  if (options.width < 1 || options.height < 1 || options.width > kMaxSide ||
      options.height > kMaxSide) {
    m.fail("bad video size " + std::to_string(options.width) + "x" +
           std::to_string(options.height) + " (each side must be 1.." + std::to_string(kMaxSide) +
           " pixels)");
  }
  if (!(options.fps > 0 && options.fps <= 1000)) {
    m.fail("bad frame rate " + std::to_string(options.fps) + " (must be in (0, 1000] fps)");
  }
  if (options.quality < 0 || options.quality > 51) {
    m.fail("bad quality " + std::to_string(options.quality) + " (must be 0..51)");
  }
  if (options.threads < 1 || options.threads > 64) {
    m.fail("bad encoder thread count " + std::to_string(options.threads) + " (must be 1..64)");
  }
  if (options.codec == "auto") {
    const std::vector<std::string> codecs = available_video_codecs();
    if (codecs.empty()) m.fail("this FFmpeg build has neither libx264 nor the mpeg4 encoder");
    m.codec = codecs.front();
  } else if (options.codec == "h264" || options.codec == "mpeg4") {
    m.codec = options.codec;
  } else {
    m.fail("unknown video codec '" + options.codec + "' (expected auto, h264 or mpeg4)");
  }
  m.coded_w = options.width + (options.width & 1);
  m.coded_h = options.height + (options.height & 1);
  if (m.coded_w != options.width || m.coded_h != options.height) {
    m.padded.resize(4 * static_cast<size_t>(m.coded_w) * m.coded_h);
  }

  check_video_name(path);
  const char* muxer = muxer_for(path);
  try {
    check_output_path(path);
  } catch (const InputError& e) {
    throw VideoError(e.what());
  }
  remove_stale_temporaries(path);
  m.tmp = path + ".tmp." + std::to_string(::getpid());
  const int err = avformat_alloc_output_context2(&m.format, nullptr, muxer, m.tmp.c_str());
  if (err < 0 || !m.format)
    m.fail(av_error(std::string("cannot set up the ") + muxer + " muxer", err));
  m.format->flags |= AVFMT_FLAG_BITEXACT;
  m.open_encoder();
  try {
    m.open_file();
  } catch (...) {
    m.close();
    std::error_code ec;
    std::filesystem::remove(m.tmp, ec);
    throw;
  }
}

VideoWriter::~VideoWriter() {
  if (!impl_ || impl_->finished) return;
  impl_->close();
  std::error_code ec;
  std::filesystem::remove(impl_->tmp, ec);  // nothing half-written stays behind
}

void VideoWriter::add_frame(const uint8_t* rgba_top_down) {
  const FpTrapsMasked masked;
  Impl& m = *impl_;
  if (m.finished) m.fail("add_frame after finish");
  const int w = m.options.width, h = m.options.height;
  const uint8_t* src = rgba_top_down;
  if (!m.padded.empty()) {
    // Odd size: repeat the last column and row into the even-sized buffer.
    const size_t in_row = 4 * static_cast<size_t>(w), out_row = 4 * static_cast<size_t>(m.coded_w);
    for (int y = 0; y < m.coded_h; ++y) {
      const uint8_t* s = rgba_top_down + in_row * std::min(y, h - 1);
      uint8_t* d = m.padded.data() + out_row * y;
      std::memcpy(d, s, in_row);
      if (m.coded_w != w) std::memcpy(d + in_row, s + in_row - 4, 4);
    }
    src = m.padded.data();
  }
  int err = av_frame_make_writable(m.frame.get());
  if (err < 0) m.fail(av_error("cannot reuse the frame buffer", err));
  const uint8_t* planes[1] = {src};
  const int strides[1] = {4 * m.coded_w};
  sws_scale(m.sws.get(), planes, strides, 0, m.coded_h, m.frame->data, m.frame->linesize);
  m.frame->pts = m.next_pts++;
  err = avcodec_send_frame(m.encoder.get(), m.frame.get());
  if (err < 0) m.fail(av_error("encoding failed", err));
  m.drain(false);
}

void VideoWriter::finish() {
  const FpTrapsMasked masked;
  Impl& m = *impl_;
  if (m.finished) return;
  if (m.next_pts == 0) m.fail("no frames were added; an empty video is not written");
  const int err = avcodec_send_frame(m.encoder.get(), nullptr);
  if (err < 0) m.fail(av_error("cannot flush the encoder", err));
  m.drain(true);
  const int terr = av_write_trailer(m.format);
  if (terr < 0) m.fail(av_error("cannot finish " + m.tmp, terr));
  const int cerr = avio_closep(&m.format->pb);
  if (cerr < 0) m.fail(av_error("cannot close " + m.tmp, cerr));
  std::error_code ec;
  std::filesystem::rename(m.tmp, m.path, ec);
  if (ec) m.fail("cannot rename " + m.tmp + " into place: " + ec.message());
  m.finished = true;
  m.close();
}

std::string VideoWriter::codec_name() const {
  return impl_->codec;
}
int VideoWriter::encoded_width() const {
  return impl_->coded_w;
}
int VideoWriter::encoded_height() const {
  return impl_->coded_h;
}
int VideoWriter::frames() const {
  return static_cast<int>(impl_->next_pts);
}

void check_video_name(const std::string& path) {
  if (!muxer_for(path))
    throw VideoError(path +
                     ": cannot choose a container from the extension: use .mp4 (or .m4v) or "
                     ".mkv (WebM, AVI and others are not written)");
}

}  // namespace plastivox::render
