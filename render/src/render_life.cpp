#include "plastivox/render/render_life.hpp"

#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/output_path.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/video_writer.hpp"

namespace plastivox::render {
namespace {

void say(const LogFn& log, const std::string& line) {
  if (log) log(line);
}

// A bounded first-in first-out hand-over between two threads. close() ends it after the
// items already in it; cancel() ends it at once for both sides (a failure elsewhere).
template <class T>
class Channel {
 public:
  explicit Channel(size_t capacity) : capacity_(capacity) {}

  // Waits while full; false if cancelled (the item is dropped).
  bool push(T&& item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return cancelled_ || items_.size() < capacity_; });
    if (cancelled_) return false;
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }
  // Waits while empty; false once closed and drained, or cancelled.
  bool pop(T& out) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return cancelled_ || closed_ || !items_.empty(); });
    if (cancelled_ || items_.empty()) return false;
    out = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return true;
  }
  void close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    not_empty_.notify_all();
  }
  void cancel() {
    std::lock_guard<std::mutex> lock(mutex_);
    cancelled_ = true;
    not_empty_.notify_all();
    not_full_.notify_all();
  }

 private:
  const size_t capacity_;
  std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  bool closed_ = false, cancelled_ = false;
};

// The source to draw in `color`, when it is not `source` itself: colouring by actuation draws
// the frames with the actuation signal, which a recorded life has only when recorded with it
// (simulate --record-control).
std::optional<LifeSource> with_color_channels(const LifeSource& source, ColorMode color) {
  if (color != ColorMode::kActuation) return std::nullopt;
  if (!source.frames_with_signal || (source.recorded && !source.recorded->result.recording.control))
    throw RenderError(source.path +
                      ": --color actuation needs the actuation signal, and this life was "
                      "recorded without it: record it with plastivox simulate ROBOT --record "
                      "LIFE.h5 --record-control");
  LifeSource out = source;
  out.frames = source.frames_with_signal;
  return out;
}

}  // namespace

FrameRenderer::FrameRenderer(const FrameStyle& style) : style_(style) {
  ctx_ = std::make_unique<OffscreenContext>(style.width, style.height);
  scene_ = std::make_unique<SceneRenderer>(*ctx_);
  if (style.overlay.any()) ui_ = std::make_unique<ImGuiLayer>(*ctx_, overlay_fonts(style.height));
}

FrameRenderer::~FrameRenderer() {
  ui_.reset();  // GL objects go before their context
  scene_.reset();
}

Camera styled_camera(const FrameStyle& style, Camera c) {
  c.orthographic = style.orthographic;
  c.azimuth_deg = style.azimuth_deg;
  c.elevation_deg = style.elevation_deg;
  return c;
}

std::vector<uint8_t> FrameRenderer::render(const FrameSet& life, const Frame& frame,
                                           const ColorScale& scale, const std::string& treatment) {
  return render(life, frame, scale, treatment,
                styled_camera(style_, follow_camera(*life.model, frame, style_.zoom)));
}

std::vector<uint8_t> FrameRenderer::render(const FrameSet& life, const Frame& frame,
                                           const ColorScale& scale, const std::string& treatment,
                                           const Camera& camera) {
  const Model& model = *life.model;
  Scene scene;
  scene.boxes = frame_boxes(model, frame, scale);
  show_world(scene, model);
  scene.camera = camera;
  scene.grid_spacing = model.size;
  scene.lit = style_.lit;
  scene.shadows = style_.shadows;
  scene.outlines = style_.lit;
  scene.samples = style_.samples;
  scene_->draw(scene);
  if (ui_) {
    OverlayInfo info;
    info.time = frame.time;
    info.treatment = treatment;
    info.displacement = displacement_so_far(life, frame);
    info.voxel_size = model.size;
    info.pixels_per_metre = scene.camera.pixels_per_metre(style_.height);
    ui_->begin_frame();
    draw_overlay(*ui_, style_.width, style_.height, scale, info, style_.overlay);
    ui_->end_frame_and_render();
  }
  return ctx_->read_rgba();
}

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw RenderError(path + ": cannot write: folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw RenderError(path + ": cannot write: folder " + dir.string() + " is not writable");
  try {  // a device, pipe, socket or folder there
    plastivox::check_output_path(path);
  } catch (const InputError& e) {
    throw RenderError(e.what());
  }
}

std::vector<uint8_t> render_frame(const LifeSource& given, double time, const FrameStyle& style) {
  check_render_target(style.width, style.height, style.samples);  // before simulating
  const std::optional<LifeSource> colored = with_color_channels(given, style.color);
  const LifeSource& source = colored ? *colored : given;
  const FrameSet life = take_frame_set(source, {time});
  const ColorScale scale =
      make_color_scale(style.color, *life.model, {&life.frames[0]}, style.color_range);
  const Camera camera =
      life_cameras(*life.model, {&life.frames[0]}, styled_camera(style, Camera{}),
                   static_cast<double>(style.width) / style.height, style.zoom)[0];
  FrameRenderer renderer(style);
  return renderer.render(life, life.frames[0], scale, to_string(source.physics.treatment), camera);
}

void check_video_request(const VideoJob& job, const std::string& out) {
  if (!(job.fps > 0 && job.fps <= 1000)) throw RenderError("--fps must be in (0, 1000]");
  if (job.stride < 1) throw RenderError("--stride must be a positive whole number");
  if (job.codec != "auto" && job.codec != "h264" && job.codec != "mpeg4")
    throw RenderError("--codec: unknown video codec '" + job.codec +
                      "' (expected auto, h264 or mpeg4)");
  check_video_name(out);  // the writer opens after the simulation, when the scale needs it
  check_output_path(out);
}

VideoSummary render_video(const LifeSource& given, const FrameStyle& style, const VideoJob& job,
                          const std::string& out, const LogFn& log) {
  check_video_request(job, out);
  check_render_target(style.width, style.height, style.samples);  // before simulating
  const std::optional<LifeSource> colored = with_color_channels(given, style.color);
  const LifeSource& source = colored ? *colored : given;
  const std::string& source_path = source.path;
  const double end = job.end < 0 ? source.physics.duration : job.end;
  if (!(job.start >= 0 && end <= source.physics.duration + 1e-9 && job.start < end))
    throw RenderError(source_path + ": time range [" + std::to_string(job.start) + ", " +
                      std::to_string(end) + "] s is not inside the life [0, " +
                      std::to_string(source.physics.duration) + "] s");
  const double step = job.stride / job.fps;
  const int count = static_cast<int>(std::floor((end - job.start) / step + 1e-9));
  if (count < 1) throw RenderError("the time range holds no frame at this --fps and --stride");
  std::vector<double> times(count);
  for (int k = 0; k < count; ++k) times[k] = job.start + k * step;

  // Three stages run at once: the (single-threaded) simulation, drawing on this thread
  // (llvmpipe adds its own threads) and encoding. Each stage works in frame order and hands
  // frames on in order, so the bytes are those of doing one after the other. Every colour
  // mode but "change" and data-range "stiffness" depends on the model alone; those span the
  // stiffness of all frames, and the life camera path spans all poses, so there the
  // simulation finishes before drawing starts.
  VideoSummary summary;
  const auto start = std::chrono::steady_clock::now();
  const std::shared_ptr<const Model> model = source.model;
  const bool scale_needs_frames =
      source.recorded || style.camera == FrameStyle::CameraPath::kLife ||
      style.color == ColorMode::kChange ||
      (style.color == ColorMode::kStiffness && style.color_range == ColorRange::kData);
  std::vector<SourcedFrame> simulated;  // all frames, when the scale needs them
  if (scale_needs_frames) {
    say(log,
        source.recorded
            ? "reading " + std::to_string(count) + " frames of the recorded life " + source_path
            : "simulating " + source_path + " (" + std::to_string(count) + " frames to capture)");
    simulated.reserve(count);
    take_frames(source, times, [&](SourcedFrame&& f) {
      simulated.push_back(std::move(f));
      return true;
    });
    if (!source.recorded) summary.simulate_seconds = seconds_since(start);
  } else {
    say(log, "simulating " + source_path + " (" + std::to_string(count) +
                 " frames to capture) while drawing and encoding");
  }
  std::vector<const Frame*> frames;
  for (const SourcedFrame& f : simulated) frames.push_back(&f.frame);
  const ColorScale scale = make_color_scale(style.color, *model, frames, style.color_range);
  const std::vector<Camera> cameras =
      style.camera == FrameStyle::CameraPath::kLife
          ? life_cameras(*model, frames, styled_camera(style, Camera{}),
                         static_cast<double>(style.width) / style.height, style.zoom)
          : std::vector<Camera>{};

  VideoOptions vo;
  vo.width = style.width;
  vo.height = style.height;
  vo.fps = job.fps;
  vo.codec = job.codec;
  VideoWriter writer(out, vo);
  FrameRenderer renderer(style);
  const std::string treatment = to_string(source.physics.treatment);

  Channel<SourcedFrame> from_simulation(32);  // ~150 kB a frame for 1000 voxels
  Channel<std::vector<uint8_t>> to_encoder(3);
  std::exception_ptr simulation_error, encoder_error;
  double simulation_seconds = 0;
  std::thread simulation, encoder;
  // Declared after the writer: on any exit the workers are stopped and joined before the
  // writer (and its temporary file) goes.
  struct Workers {
    Channel<SourcedFrame>& a;
    Channel<std::vector<uint8_t>>& b;
    std::thread& s;
    std::thread& e;
    ~Workers() {
      a.cancel();
      b.cancel();
      if (s.joinable()) s.join();
      if (e.joinable()) e.join();
    }
  } workers{from_simulation, to_encoder, simulation, encoder};

  if (!scale_needs_frames) {
    simulation = std::thread([&] {
      try {
        take_frames(source, times,
                    [&](SourcedFrame&& f) { return from_simulation.push(std::move(f)); });
      } catch (...) {
        simulation_error = std::current_exception();
      }
      // The thread's CPU time: its wall time would include waiting for the drawing.
      timespec cpu{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu);
      simulation_seconds = cpu.tv_sec + 1e-9 * cpu.tv_nsec;
      from_simulation.close();
    });
  }
  encoder = std::thread([&] {
    try {
      std::vector<uint8_t> rgba;
      while (to_encoder.pop(rgba)) writer.add_frame(rgba.data());
    } catch (...) {
      encoder_error = std::current_exception();
      to_encoder.cancel();
    }
  });

  const auto draw_start = std::chrono::steady_clock::now();
  int drawn = 0;
  for (int k = 0; k < count; ++k) {
    SourcedFrame f;
    if (scale_needs_frames)
      f = std::move(simulated[k]);
    else if (!from_simulation.pop(f))
      break;        // the simulation failed
    FrameSet life;  // what the overlay needs of the life: the model and settling
    life.model = model;
    life.settled = f.settled;
    life.com_settled = f.com_settled;
    std::vector<uint8_t> rgba = cameras.empty()
                                    ? renderer.render(life, f.frame, scale, treatment)
                                    : renderer.render(life, f.frame, scale, treatment, cameras[k]);
    if (!to_encoder.push(std::move(rgba))) break;  // failed
    ++drawn;
    if ((k + 1) % 30 == 0 || k + 1 == count)
      say(log, "frame " + std::to_string(k + 1) + "/" + std::to_string(count));
  }
  to_encoder.close();
  // Every frame is drawn, or something failed: either way the simulation has nothing more
  // to hand over (and must not wait for room to do so).
  from_simulation.cancel();
  if (simulation.joinable()) simulation.join();
  encoder.join();
  if (simulation_error) std::rethrow_exception(simulation_error);
  if (encoder_error) std::rethrow_exception(encoder_error);
  if (drawn != count) throw RenderError(source_path + ": the simulation stopped early");
  writer.finish();
  if (!scale_needs_frames) summary.simulate_seconds = simulation_seconds;
  summary.render_seconds = seconds_since(draw_start);
  summary.frames = count;
  summary.duration_s = count / job.fps;
  summary.codec = writer.codec_name();
  return summary;
}

}  // namespace plastivox::render
