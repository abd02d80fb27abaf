// plastivox: evolve, simulate, analyse and render soft voxel robots that develop.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cli.hpp"
#include "plastivox/base/one_line.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox_version.hpp"

namespace {

const char* kUsage =
    "usage: plastivox <command> [options]\n"
    "commands:\n"
    "  simulate [ROBOT] [--treatment STIMULUS] [--task NAME] [--preset NAME] [--duration S]\n"
    "           [--json]\n"
    "           simulate a robot file (.json plastivox robot or .vxa); no ROBOT: the built-in\n"
    "           ~500-voxel demo walker. --physics '{\"field\": value, ...}' overrides\n"
    "           physics fields (names as in docs/robot-format.md)\n"
    "  demo     simulate the demo walker under each treatment and print a summary\n"
    "  evolve   --config FILE --out RESULTS.h5 [--threads N]\n"
    "           run an evolution (AFPO over four CPPNs); the same command resumes a killed\n"
    "           run from its last checkpoint. --print-default-config prints a commented\n"
    "           default config (docs/evolution.md)\n"
    "  inspect  RESULTS.h5 [--json]\n"
    "           summarise a results file: treatment, seed, generations, champion, digest\n"
    "  hausdorff A B [--rotations none|paper|all] [--translation none|integer] [--json]\n"
    "           Hausdorff distance between two robots' filled voxels (.json or .vxa), in voxel\n"
    "           lengths, minimised over B's placements: paper = the paper's 8 orientations\n"
    "           (default), all = the 24 cube rotations with optimal integer translation\n"
    "  export   RESULTS.h5 --out ROBOT.vxa|ROBOT.json [--generation G]\n"
    "           write the champion at generation G (default: the last) as a VXA file for\n"
    "           the authors' simulator or as a plastivox robot file\n"
    "  analyze  [TREATMENT=]RESULTS.h5|ROBOT [...] --out DIR [--generation G]\n"
    "           [--threads N] [--robustness-draws N] [--robustness-sampling linear|log]\n"
    "           [--seed S] [--rotations none|paper|all] [--translation none|integer]\n"
    "           [--resamples N] [--treatments none,stress,pressure] [--allow-mixed-physics]\n"
    "           analyse run champions: robustness, canalization, diversity, body plans,\n"
    "           bootstrap statistics -> DIR/stats.json, CSV tables, analysis.h5,\n"
    "           report.html; rerun after a kill to resume (docs/analysis.md)\n"
    "  robustness [TREATMENT=]RESULTS.h5|ROBOT [...] [--battery default|paper|small|FILE]\n"
    "           [--out DIR] [--seed S] [--threads N] [--estimate-only]\n"
    "           the robustness battery: every champion's fitness kept under graded\n"
    "           perturbations, compared between treatments (docs/analysis.md)\n"
    "  render   ROBOT_OR_RESULTS --out frame.png [--time T] [--color MODE] [--size WxH]\n"
    "           one frame as PNG; MODE: congenital, stiffness, change, alpha, phase,\n"
    "           stimulus, actuation;\n"
    "           --no-overlay (or --no-colorbar/-time/-treatment/-displacement/-scalebar)\n"
    "           --antialias msaa|edge|none (render, gallery: msaa; video: edge)\n"
    "  video    ROBOT_OR_RESULTS --out life.mp4 [--color MODE] [--fps F] [--size WxH]\n"
    "           [--start S --end S] [--stride N]   the life as MP4 (default 5.2 s, 30 fps)\n"
    "  view     LIFE.h5|RESULTS.h5|ROBOT --out page.html [--fps F] [--generation G]\n"
    "           the life in an interactive 3-D page (opens offline, from file://)\n"
    "  gallery  RESULTS.h5 [RESULTS.h5 ...] --out gallery.png [--size WxH] [--columns N]\n"
    "  archive  RESULTS.h5 --out DIR [--axes X,Y] [--elites N] [--no-gallery]\n"
    "           a MAP-Elites run's archive: map by fitness, QD curve, table, elites' gallery\n"
    "  figures  STATS.json --out DIR [--size WxH] [--format png,svg] [--no-combined]\n"
    "           Fig. 5 panels A-F (PNG and SVG) from plastivox analyze's stats.json\n"
    "  experiment [--config FILE | --preset NAME] --out DIR [--threads N]\n"
    "           [--force STAGE,...] [--run LABEL] [--estimate-only] [--print-preset NAME]\n"
    "           the whole study: evolve, analyse, render, report (resumable); NAME: default,\n"
    "           tiny, gecco2018, a task's baseline or walk-/rough-distributed (see --help)\n"
    "  optimize ROBOT --out OPTIMISED.json [--wrt phase,stiffness] [--method adam|sgd]\n"
    "           [--steps N] [--lr X]   gradient ascent of the robot's fitness through its\n"
    "           life; a log of fitness per step (docs/gradients.md)\n"
    "  version  print version and commit\n"
    "plastivox CMD --help (or plastivox help CMD) prints a command's options and an example.\n";

// The commands main() dispatches to, by name.
using namespace plastivox::cli;
struct Command {
  const char* name;
  int (*run)(const Args&);
};
// One command a row (clang-format would pack sixteen rows into columns).
// clang-format off
const Command kCommands[] = {
    {"simulate", cmd_simulate},
    {"demo", cmd_demo},
    {"evolve", cmd_evolve},
    {"inspect", cmd_inspect},
    {"hausdorff", cmd_hausdorff},
    {"export", cmd_export},
    {"analyze", cmd_analyze},
    {"render", cmd_render},
    {"robustness", cmd_robustness},
    {"video", cmd_video},
    {"view", cmd_view},
    {"gallery", cmd_gallery},
    {"archive", cmd_archive},
    {"figures", cmd_figures},
    {"experiment", cmd_experiment},
    {"optimize", cmd_optimize},
};
// clang-format on

// Levenshtein distance: insertions, deletions and substitutions of one character.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// One line for a command that is not one: the nearest commands by edit distance (within a
// third of the longer name, at least 2), else the list, instead of the 47-line usage.
std::string unknown_command(const std::string& cmd) {
  std::vector<std::string> names = {"help", "version"};
  for (const Command& c : kCommands) names.push_back(c.name);
  size_t best = std::string::npos;
  std::string nearest, all;
  for (const std::string& name : names) {
    all += (all.empty() ? "" : ", ") + name;
    const size_t d = edit_distance(cmd, name);
    if (d > std::max<size_t>(2, std::max(cmd.size(), name.size()) / 3)) continue;
    if (d < best) {
      best = d;
      nearest.clear();
    }
    if (d == best) nearest += (nearest.empty() ? "" : " or ") + name;
  }
  if (!nearest.empty())
    return "unknown command '" + cmd + "'; did you mean " + nearest +
           "? (plastivox --help lists the commands)";
  return "unknown command '" + cmd + "' (the commands: " + all + ")";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace plastivox::cli;
  using plastivox::UsageError;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string cmd = argv[1];
  Args args(argv + 2, argv + argc);
  // plastivox CMD --help|-h and plastivox help CMD: the command's own usage, exit 0.
  if (const char* help = command_help(cmd); help && wants_help(args)) {
    std::fputs(help, stdout);
    return 0;
  }
  if (cmd == "help" && !args.empty()) {
    if (const char* help = command_help(args[0])) {
      std::fputs(help, stdout);
      return 0;
    }
    std::fprintf(stderr, "plastivox help: %s\n",
                 plastivox::one_line(unknown_command(args[0])).c_str());
    return 2;
  }
  try {
    for (const Command& c : kCommands)
      if (cmd == c.name) return c.run(args);
    if (cmd == "version" || cmd == "--version") {
      std::printf("plastivox %s (commit %s)\n", PLASTIVOX_VERSION, plastivox::build_git_commit());
      return 0;
    }
    if (cmd == "help" || cmd == "--help" || cmd == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fprintf(stderr, "plastivox: %s\n", plastivox::one_line(unknown_command(cmd)).c_str());
    return 2;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "plastivox %s: %s (plastivox %s --help lists the options)\n", cmd.c_str(),
                 e.what(), cmd.c_str());
    return 2;
  } catch (const std::bad_alloc&) {  // never the bare "std::bad_alloc"
    std::fprintf(stderr,
                 "plastivox %s: error: out of memory (the input needs more memory than this "
                 "machine has)\n",
                 cmd.c_str());
    return 1;
  } catch (const std::exception& e) {
    // One line whatever the message quotes (a damaged tag name, a path with a newline).
    std::fprintf(stderr, "plastivox %s: error: %s\n", cmd.c_str(),
                 plastivox::one_line(e.what()).c_str());
    return 1;
  }
}

// LeakSanitizer (the sanitizer CI job) reads this hook: Mesa's libOSMesa keeps a few small
// allocations per context past OSMesaDestroyContext; they are the library's, not ours.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libOSMesa.so\n";
}
