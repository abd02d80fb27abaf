#include "plastivox/render/render_life.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/video_writer.hpp"

namespace plastivox::render {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void say(const LogFn& log, const std::string& line) {
  if (log) log(line);
}

}  // namespace

LifeRenderer::LifeRenderer(const FrameStyle& style) : style_(style) {
  ctx_ = std::make_unique<OffscreenContext>(style.width, style.height);
  scene_ = std::make_unique<SceneRenderer>(*ctx_);
  if (style.overlay.any()) ui_ = std::make_unique<ImGuiLayer>(*ctx_, overlay_fonts(style.height));
}

LifeRenderer::~LifeRenderer() {
  ui_.reset();  // GL objects go before their context
  scene_.reset();
}

std::vector<uint8_t> LifeRenderer::render(const Life& life, const Frame& frame,
                                          const ColorScale& scale, const std::string& treatment) {
  const Model& model = *life.model;
  Scene scene;
  scene.boxes = frame_boxes(model, frame, scale);
  scene.camera = follow_camera(model, frame, style_.zoom);
  scene.camera.orthographic = style_.orthographic;
  scene.camera.azimuth_deg = style_.azimuth_deg;
  scene.camera.elevation_deg = style_.elevation_deg;
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
  if (fs::is_directory(p, ec)) throw RenderError(path + ": cannot write: it is a folder");
}

void render_frame_file(const std::string& source_path, double time, const FrameStyle& style,
                       const std::string& out, const LogFn& log) {
  check_output_path(out);
  const LifeSource source = load_life_source(source_path);
  for (const std::string& w : source.warnings) say(log, "warning: " + w);
  say(log, "simulating " + source_path + " to t = " + std::to_string(time) + " s");
  const Life life = simulate_life(source, {time});
  const ColorScale scale = make_color_scale(style.color, *life.model, {&life.frames[0]});
  LifeRenderer renderer(style);
  const std::vector<uint8_t> rgba =
      renderer.render(life, life.frames[0], scale, to_string(source.physics.treatment));
  write_png(out, rgba, style.width, style.height);
}

VideoSummary render_video_file(const std::string& source_path, const FrameStyle& style,
                               const VideoJob& job, const std::string& out, const LogFn& log) {
  if (!(job.fps > 0 && job.fps <= 1000)) throw RenderError("--fps must be in (0, 1000]");
  if (job.stride < 1) throw RenderError("--stride must be a positive whole number");
  check_output_path(out);
  const LifeSource source = load_life_source(source_path);
  for (const std::string& w : source.warnings) say(log, "warning: " + w);
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

  VideoSummary summary;
  auto t0 = std::chrono::steady_clock::now();
  say(log, "simulating " + source_path + " (" + std::to_string(count) + " frames to capture)");
  const Life life = simulate_life(source, times);
  summary.simulate_seconds = seconds_since(t0);

  std::vector<const Frame*> frames;
  for (const Frame& f : life.frames) frames.push_back(&f);
  const ColorScale scale = make_color_scale(style.color, *life.model, frames);
  t0 = std::chrono::steady_clock::now();
  VideoOptions vo;
  vo.width = style.width;
  vo.height = style.height;
  vo.fps = job.fps;
  vo.codec = job.codec;
  VideoWriter writer(out, vo);
  LifeRenderer renderer(style);
  const std::string treatment = to_string(source.physics.treatment);
  for (int k = 0; k < count; ++k) {
    const std::vector<uint8_t> rgba = renderer.render(life, life.frames[k], scale, treatment);
    writer.add_frame(rgba.data());
    if ((k + 1) % 30 == 0 || k + 1 == count)
      say(log, "frame " + std::to_string(k + 1) + "/" + std::to_string(count));
  }
  writer.finish();
  summary.render_seconds = seconds_since(t0);
  summary.frames = count;
  summary.duration_s = count / job.fps;
  summary.codec = writer.codec_name();
  return summary;
}

}  // namespace plastivox::render
