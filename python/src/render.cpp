// Rendering for Python: one frame of a robot's life (off-screen, OSMesa) as an (h, w, 3)
// uint8 array, optionally written as a PNG; the same call as `plastivox render`. Also a
// simulator's present state (VoxelEnv.render).
#include <cmath>
#include <memory>
#include <mutex>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/life.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/render_life.hpp"

namespace plastivox::py {
namespace {

// One frame at a time: the off-screen GL context and its UI layer are per process, and two
// threads setting them up at once failed an assertion in the UI backend ("Already
// initialized"). Callers release the GIL first, so a waiting thread holds nothing.
std::mutex renderer;

// RGBA8 rows as an (h, w, 3) uint8 array.
pyb::array_t<uint8_t> rgb_array(const std::vector<uint8_t>& rgba, int width, int height) {
  pyb::array_t<uint8_t> rgb({pyb::ssize_t{height}, pyb::ssize_t{width}, pyb::ssize_t{3}});
  uint8_t* dst = rgb.mutable_data();
  for (size_t p = 0; p < static_cast<size_t>(width) * height; ++p)
    for (int c = 0; c < 3; ++c) dst[3 * p + c] = rgba[4 * p + c];
  return rgb;
}

pyb::array_t<uint8_t> render_source(const render::LifeSource& source, double time,
                                    const std::string& color, int width, int height, bool overlay,
                                    double zoom, double azimuth, double elevation,
                                    const std::string& antialias, const std::string& out) {
  // The life ends at its first step past the duration, so its own end time (Result.sim_time,
  // VoxelEnv's last info["time"]) is within it; the frames' source refuses a time past the
  // last step precisely (plastivox/life.hpp).
  const double end = source.physics.duration + (source.model ? longest_step(*source.model) : 0.0);
  if (!(time >= 0 && time <= end))
    throw std::invalid_argument("time: must be within the life, [0, " +
                                std::to_string(source.physics.duration) +
                                "] s (it ends at its first step past that)");
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("size: each side must be 1..16384 pixels");
  if (!(zoom > 0 && std::isfinite(zoom))) throw std::invalid_argument("zoom: must be > 0");
  if (!(elevation > -90 && elevation <= 90 && std::isfinite(azimuth)))
    throw std::invalid_argument("elevation: must be in (-90, 90] degrees");
  render::FrameStyle style;
  style.width = width;
  style.height = height;
  try {
    style.color = render::parse_color_mode(color);
  } catch (const render::RenderError& e) {
    throw std::invalid_argument(std::string("color: ") + e.what());
  }
  if (!overlay) style.overlay = {false, false, false, false, false};
  style.zoom = zoom;
  style.azimuth_deg = azimuth;
  style.elevation_deg = elevation;
  // As `plastivox render --antialias`: msaa = 4 samples.
  if (antialias == "msaa")
    style.samples = 4;
  else if (antialias == "none")
    style.samples = 1;
  else if (antialias == "edge")
    style.samples = render::kEdgeAntialiasing;
  else
    throw std::invalid_argument("antialias: expected msaa, edge or none, got '" + antialias + "'");
  if (!out.empty()) {
    // The frame is encoded as PNG whatever the name says, as `plastivox render --out` refuses.
    if (!render::is_png_name(out))
      throw std::invalid_argument("out: " + out + ": render writes PNG only; name the file .png");
    render::check_output_path(out);
  }
  std::vector<uint8_t> rgba;
  {
    pyb::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> one_at_a_time(renderer);
    rgba = render::render_frame(source, time, style);
    if (!out.empty()) render::write_png(out, rgba, width, height);
  }
  return rgb_array(rgba, width, height);
}

}  // namespace

StatePainter::StatePainter() = default;

StatePainter::~StatePainter() {
  // Its GL and UI contexts go under the lock: setting the UI's current context is global. The
  // holder of the lock never waits for the GIL, so waiting here with it cannot deadlock.
  const std::lock_guard<std::mutex> one_at_a_time(renderer);
  drawer_.reset();
}

pyb::array_t<uint8_t> StatePainter::draw(const std::shared_ptr<const Model>& model,
                                         const State& state, int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("render_size: each side must be 1..16384 pixels");
  render::FrameStyle style;
  style.width = width;
  style.height = height;
  style.samples = 4;  // as render()'s default, msaa
  render::FrameSet life;
  life.model = model;
  life.frames.push_back(capture_frame(state));
  life.settled = state.settled;
  life.com_settled = state.com_settled;
  std::vector<uint8_t> rgba;
  {
    pyb::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> one_at_a_time(renderer);
    // As render::render_frame draws the frame of a life at a time: the same scale and camera.
    const Frame& frame = life.frames[0];
    const render::ColorScale scale =
        render::make_color_scale(style.color, *model, {&frame}, style.color_range);
    const render::Camera camera =
        render::life_cameras(*model, {&frame}, render::styled_camera(style, render::Camera{}),
                             static_cast<double>(width) / height, style.zoom)[0];
    if (!drawer_ || drawer_->style().width != width || drawer_->style().height != height)
      drawer_ = std::make_unique<render::FrameRenderer>(style);
    rgba = drawer_->render(life, frame, scale, to_string(model->def.treatment), camera);
  }
  return rgb_array(rgba, width, height);
}

void bind_render(pyb::module_& m) {
  m.def("render_robot", [](const PyRobot& robot, double time, const std::string& color, int width,
                           int height, bool overlay, double zoom, double azimuth, double elevation,
                           const std::string& antialias, const std::string& out) {
    const render::LifeSource source =
        render::simulated_life_source(robot.source, robot.def, robot.physics, robot.def.name);
    return render_source(source, time, color, width, height, overlay, zoom, azimuth, elevation,
                         antialias, out);
  });
  m.def("render_file",
        [](const std::string& path, int generation, double time, const std::string& color,
           int width, int height, bool overlay, double zoom, double azimuth, double elevation,
           const std::string& antialias, const std::string& out) {
          // A generation names a results file's champion; anything else has one life.
          const auto not_results = [&](const char* what) {
            return std::invalid_argument("generation: applies to a results file (.h5), and " +
                                         path + " is " + what);
          };
          if (generation != -1 && !path.ends_with(".h5")) throw not_results("a robot file");
          const render::LifeSource source = render::load_life_source(path, generation);
          if (generation != -1 && source.recorded) throw not_results("a recorded life");
          for (const std::string& w : source.warnings) warn(w);  // named the file already
          return render_source(source, time, color, width, height, overlay, zoom, azimuth,
                               elevation, antialias, out);
        });
}

}  // namespace plastivox::py
