// plastivox view LIFE.h5|RESULTS.h5|ROBOT [...] --out page.html [--fps F] [--generation G]:
// lives as one self-contained page with the interactive 3-D viewer (three.js inlined; opens
// from file:// with no network), one viewer and, for several inputs, a button per life. A
// recorded life is shown as recorded; a robot or a run's champion is simulated once,
// recording F frames per simulated second.
#include <cstdio>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/render_files.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {

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
  // Each input loaded or simulated once (render::show_life), then packed into one page.
  std::vector<render::ShownLife> shown;
  for (const std::string& file : args) {
    shown.push_back(render::show_life(file, generation, fps,
                                      [](const std::string& m) { log_line("view", m); }));
    if (!shown.back().failure.empty()) {
      std::fprintf(stderr, "plastivox view: %s: %s\n", file.c_str(), shown.back().failure.c_str());
      return 3;
    }
  }
  std::vector<render::ViewerLife> lives;
  size_t frames = 0;
  for (const render::ShownLife& s : shown) {
    lives.push_back(s.life());
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
