// plastivox view LIFE.h5|RESULTS.h5|ROBOT [...] --out page.html [--fps F] [--generation G]:
// lives as one self-contained page with the interactive 3-D viewer (three.js inlined; opens
// from file:// with no network), one viewer and, for several inputs, a button per life. A
// recorded life is shown as recorded; a robot or a run's champion is simulated once,
// recording F frames per simulated second.
#include <cstdio>
#include <stdexcept>

#include "plastivox/atomic_file.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/robot_file.hpp"  // InputError
#include "plastivox/simulator.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {
namespace {

// One input's life: its model and frames (owned here; the ViewerLife points at them).
struct Shown {
  Model model;
  Recording recording;
  render::ViewerLife life;
};

// Loads (a recorded life) or simulates (anything else) one input; false if it went unstable.
bool show(const std::string& file, int generation, double fps, Shown& out) {
  const render::LifeSource source = render::load_life_source(file, generation);
  for (const std::string& w : source.warnings) log_line("view", "warning: " + w);
  render::ViewerLife& life = out.life;
  life.label = source.label;
  life.treatment = to_string(source.physics.treatment);
  const PhysicsDef& def = source.physics;
  try {
    out.model = compile(source.robot, def);
  } catch (const std::invalid_argument& e) {
    throw InputError(file + ": " + e.what());
  }
  if (source.recorded) {
    out.recording = source.recorded->recording;
    life.settled = source.recorded->settled;
    life.com_settled = source.recorded->com_settled;
    life.fitness = source.recorded->fitness;
    return true;
  }
  char what[96];
  std::snprintf(what, sizeof what, " (%g s at %g frames per second)", def.duration, fps);
  log_line("view", "simulating " + file + what);
  SimOptions options;
  options.record_fps = fps;
  SimResult r = simulate(out.model, options);
  if (r.status != SimStatus::kFinished) {
    std::fprintf(stderr, "plastivox view: %s: simulation unstable: %s\n", file.c_str(),
                 r.failure.c_str());
    return false;
  }
  out.recording = std::move(r.recording);
  life.settled = r.settled;
  life.com_settled = r.com_settled;
  life.fitness = r.fitness;
  return true;
}

}  // namespace

int cmd_view(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const double fps = parse_number(take_option(args, "--fps", "30"), "--fps");
  const int generation = parse_whole(take_option(args, "--generation", "-1"), "--generation");
  reject_unknown_options(args);
  if (args.empty())
    throw UsageError{
        "expected a recorded life, results file or robot: plastivox view LIFE.h5 "
        "--out page.html"};
  if (out.empty()) throw UsageError{"--out page.html is required"};
  if (!(fps > 0 && fps <= 1000)) throw UsageError{"--fps must be in (0, 1000]"};
  render::check_output_path(out);
  std::vector<Shown> shown(args.size());
  for (size_t i = 0; i < args.size(); ++i)
    if (!show(args[i], generation, fps, shown[i])) return 3;
  std::vector<render::ViewerLife> lives;
  size_t frames = 0;
  for (Shown& s : shown) {
    s.life.model = &s.model;
    s.life.recording = &s.recording;
    lives.push_back(s.life);
    frames += s.recording.frames.size();
  }
  const std::string how_many =
      std::to_string(lives.size()) + (lives.size() == 1 ? " life" : " lives");  // not "lifes"
  const std::string title = "plastivox · " + (lives.size() == 1 ? lives[0].label : how_many);
  const std::string page = render::viewer_page(lives, title);
  write_file_atomic(out, page);
  std::printf("wrote %s (%s, %s in all, %.1f MB; fitness %.4f voxel lengths%s)\n", out.c_str(),
              how_many.c_str(), count_of(static_cast<long long>(frames), "frame").c_str(),
              page.size() / 1e6, lives[0].fitness, lives.size() > 1 ? " for the first" : "");
  return 0;
}

}  // namespace plastivox::cli
