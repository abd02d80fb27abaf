// plastivox view LIFE.h5|RESULTS.h5|ROBOT [...] --out page.html [--fps F] [--generation G]:
// lives as one self-contained page with the interactive 3-D viewer (three.js inlined; opens
// from file:// with no network), one viewer and, for several inputs, a button per life. A
// recorded life is shown as recorded; a robot or a run's champion is simulated once,
// recording F frames per simulated second.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/viewer.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {

int cmd_view(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const std::string fps_text = take_option(args, "--fps", "");
  const std::string generation_text = take_option(args, "--generation", "");
  const double fps = fps_text.empty() ? 30 : parse_number(fps_text, "--fps");
  const int generation =
      generation_text.empty() ? -1 : parse_whole(generation_text, "--generation");
  reject_unknown_options(args);
  if (args.empty())
    throw UsageError{
        "expected a recorded life, results file or robot: plastivox view LIFE.h5 "
        "--out page.html"};
  if (out.empty()) throw UsageError{"--out page.html is required"};
  if (!(fps > 0 && fps <= 1000)) throw UsageError{"--fps must be in (0, 1000]"};
  // An option that applies to none of the inputs is refused, not ignored (as export does).
  enum Kind { kRobot, kResults, kLife };
  const auto kind = [](const std::string& file) {
    if (!file.ends_with(".h5")) return kRobot;  // load_life_source's own test
    return is_life_file(file) ? kLife : kResults;
  };
  const char* const kNames[] = {"a robot", "a results file", "a recorded life"};
  const auto refuse_unless_any = [&](const std::string& option, const std::string& given,
                                     const std::string& applies_to, std::vector<Kind> kinds) {
    if (given.empty()) return;
    for (const std::string& file : args)
      if (std::find(kinds.begin(), kinds.end(), kind(file)) != kinds.end()) return;
    throw UsageError{option + " applies to " + applies_to + "; " +
                     (args.size() == 1
                          ? args[0] + " is " + kNames[kind(args[0])]
                          : "none of the " + std::to_string(args.size()) + " inputs is one")};
  };
  refuse_unless_any("--fps", fps_text,
                    "a robot or a results file's champion, simulated here (a recorded life keeps "
                    "its own frames)",
                    {kRobot, kResults});
  refuse_unless_any("--generation", generation_text, "a results file (.h5)", {kResults});
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
  std::vector<render::ViewerItem> lives;
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
