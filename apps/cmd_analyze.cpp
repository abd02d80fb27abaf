// plastivox analyze: the run champions of several results files, measured and compared
// (docs/method.md §8) -> DIR/stats.json, CSV tables, analysis.h5 and report.html.
// The library calls are analyze_study + write_study_outputs (the data), then the report from
// the study read back from analysis.h5, as `plastivox experiment` makes it
// (plastivox/analysis/study.hpp).
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>

#include "battery_ranks.hpp"
#include "cli.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/evo/run.hpp"  // Cluster
#include "plastivox/render/error.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/viewer.hpp"

namespace plastivox::cli {
namespace {

// Ctrl-C / SIGTERM: finish the champions in progress (they are checkpointed), then stop.
std::atomic<bool> g_stop{false};
extern "C" void on_analyze_interrupt(int) {
  g_stop.store(true);
}

long long parse_integer(const std::string& option, const std::string& text, long long min) {
  size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (...) {
    used = 0;
  }
  if (used != text.size() || text.empty() || v < min)
    throw UsageError{option + " expects an integer >= " + std::to_string(min) + ", got '" + text +
                     "'"};
  return v;
}

std::vector<Treatment> parse_treatments(const std::string& list) {
  std::vector<Treatment> out;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    try {
      out.push_back(parse_treatment(name));
    } catch (const std::exception&) {
      throw UsageError{
          "--treatments expects a comma-separated list of none, stress, pressure; "
          "got '" +
          name + "'"};
    }
    start = comma + 1;
  }
  return out;
}

analysis::StudyOptions parse_options(Args& args, std::string* out, bool* viewer) {
  analysis::StudyOptions o;
  *out = take_option(args, "--out", "");
  *viewer = !take_flag(args, "--no-viewer");
  const std::string gen = take_option(args, "--generation", "last");
  if (gen != "last") o.generation = static_cast<int>(parse_integer("--generation", gen, 0));
  o.robustness_draws = static_cast<int>(
      parse_integer("--robustness-draws", take_option(args, "--robustness-draws", "10"), 1));
  const std::string sampling = take_option(args, "--robustness-sampling", "linear");
  if (sampling == "log")
    o.robustness_sampling = analysis::StiffnessDistribution::kLogUniform;
  else if (sampling != "linear")
    throw UsageError{"--robustness-sampling expects linear or log, got '" + sampling + "'"};
  const std::string rotations = take_option(args, "--rotations", "paper");
  try {
    o.rotations = analysis::parse_rotation_search(rotations);
  } catch (const std::exception&) {
    throw UsageError{"--rotations expects none, paper or all, got '" + rotations + "'"};
  }
  const std::string translation = take_option(
      args, "--translation", o.rotations == analysis::RotationSearch::kAll ? "integer" : "none");
  if (translation == "integer")
    o.translation = analysis::TranslationSearch::kInteger;
  else if (translation != "none")
    throw UsageError{"--translation expects none or integer, got '" + translation + "'"};
  o.resamples = static_cast<int>(
      parse_integer("--resamples", take_option(args, "--resamples", "10000"), 100));
  o.seed = static_cast<uint64_t>(parse_integer("--seed", take_option(args, "--seed", "1"), 0));
  o.threads = static_cast<int>(parse_integer("--threads", take_option(args, "--threads", "0"), 0));
  const std::string treatments = take_option(args, "--treatments", "");
  if (!treatments.empty()) o.treatments = parse_treatments(treatments);
  o.allow_mixed_physics = take_flag(args, "--allow-mixed-physics");
  o.keep_artifacts = take_flag(args, "--keep-artifacts");
  o.keep_vertical = take_flag(args, "--keep-vertical");
  o.battery = take_option(args, "--battery", "");
  reject_unknown_options(args);
  render::limit_raster_threads(o.threads);
  if (out->empty()) throw UsageError{"--out DIR is required"};
  if (args.empty())
    throw UsageError{
        "expected results or robot files: plastivox analyze [TREATMENT=]FILE [...] --out DIR"};
  return o;
}

// --out names a folder that analyze creates or adds to: refused before any work when
// something else sits there (a file, /dev/null) or the folder cannot be written.
void check_output_folder(const std::string& out) {
  namespace fs = std::filesystem;
  const std::string at = "--out " + out + ": ";
  struct stat st {};
  if (::stat(out.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode))
      throw InputError(at + (S_ISREG(st.st_mode) ? "is a file" : "is a device, pipe or socket") +
                       ", not a folder (analyze writes a folder of outputs)");
    if (::access(out.c_str(), W_OK | X_OK) != 0)
      throw InputError(at + "the folder is not writable");
    return;
  }
  // Not there yet: the nearest existing ancestor must be a writable folder to create it in.
  fs::path up = fs::path(out).lexically_normal();
  if (!up.has_filename()) up = up.parent_path();  // "dir/" -> "dir"
  for (up = up.parent_path(); !up.empty(); up = up.parent_path()) {
    if (::stat(up.c_str(), &st) == 0) break;
    if (up == up.root_path()) break;
  }
  if (up.empty()) up = ".";
  if (::stat(up.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw InputError(at + "cannot create the folder: " + up.string() + " is not a folder");
  if (::access(up.c_str(), W_OK | X_OK) != 0)
    throw InputError(at + "cannot create the folder: " + up.string() + " is not writable");
}

}  // namespace

int cmd_analyze(const Args& in) {
  Args args = in;
  std::string out;
  bool viewer = true;
  analysis::StudyOptions options = parse_options(args, &out, &viewer);
  check_output_folder(out);  // before any results file is read or champion simulated
  options.cache_dir = (std::filesystem::path(out) / "cache").string();
  options.command = "plastivox analyze";
  for (const std::string& a : in) options.command += " " + a;

  // Under mpirun every rank runs the same analysis and the battery's lives are shared among
  // them (battery_ranks.hpp); rank 0 alone talks and writes (checkpoints included). A stop
  // request would reach the ranks at different moments, so under MPI a kill stops it and a
  // rerun resumes from the checkpoints.
  const std::unique_ptr<evo::Cluster> mpi = join_mpi_job();
  const bool leader = !mpi || mpi->rank() == 0;
  options.battery_lives = battery_lives_over_ranks(mpi.get(), options.threads);
  options.write_cache = leader;
  if (!options.battery_lives) {
    options.stop_requested = &g_stop;
    std::signal(SIGINT, on_analyze_interrupt);
    std::signal(SIGTERM, on_analyze_interrupt);
  }
  analysis::StudyResult r;
  try {
    r = analysis::analyze_study(args, options, [leader](const analysis::StudyProgress& p) {
      if (leader) std::fprintf(stderr, "plastivox analyze: %s\n", p.message.c_str());
    });
  } catch (const analysis::StudyStopped& e) {
    std::fprintf(stderr, "plastivox analyze: %s; rerun the same command to resume\n", e.what());
    return 130;
  } catch (const std::exception& e) {
    abort_other_ranks(mpi.get(), "analyze", e);  // they would wait for ever
    throw;
  }
  if (!leader) return 0;
  // The report's 3-D viewer: every champion's life, simulated once more with frames, in
  // OUT/lives/ (--no-viewer: none).
  analysis::ReportExtras extras;
  if (viewer) {
    std::vector<render::ReportChampion> sources;
    for (const auto& c : r.champions)
      sources.push_back({c.label, r.inputs[c.input].file, c.generation});
    std::fprintf(stderr, "plastivox analyze: lives for the 3-D viewer: simulating %zu champions\n",
                 sources.size());
    const auto lives = render::write_report_lives(
        sources, out, render::kViewerFps, options.threads,
        [](const std::string& m) { std::fprintf(stderr, "plastivox analyze: %s\n", m.c_str()); });
    analysis::ReportSection section;
    section.title = "Lives in 3-D";
    section.wide = true;
    section.paragraphs.push_back(
        "Each champion's whole life (lives/): drag to orbit, scroll to zoom; pick a champion "
        "by its button.");
    section.raw_html = render::viewer_fragment(lives, true);
    if (!lives.empty()) extras.sections.push_back(section);
  }
  analysis::write_study_outputs(r, out);
  // The report is made from analysis.h5 as the experiment makes it, bodies loaded again from
  // the results files (the shared-seeded-body note compares them), so both reports agree.
  analysis::StudyResult back = analysis::read_study_result(out + "/analysis.h5");
  analysis::load_champion_bodies(back);
  analysis::write_study_report(back, out + "/report.html", extras);

  const analysis::StudyTimings& t = r.timings;
  std::printf(
      "wrote %s/{stats.json, champions.csv, statistics.csv, hausdorff.csv, analysis.h5, "
      "report.html%s}: %s, %s\n",
      out.c_str(), viewer ? ", lives/" : "",
      count_of(static_cast<long long>(r.champions.size()), "champion").c_str(),
      count_of(static_cast<long long>(r.treatments.size()), "treatment").c_str());
  std::printf(
      "time: %.2f s (load %.2f, robustness %.2f [%d simulations, %d from checkpoint], "
      "canalization %.3f, body plans %.3f, hausdorff %.3f, statistics %.3f)\n",
      t.total, t.load, t.robustness, t.robustness_simulations, t.robustness_cached, t.canalization,
      t.body_plans, t.hausdorff, t.statistics);
  if (r.battery)
    std::printf("battery: %d lives (%d unstable, %d sank); %d champions from checkpoint\n",
                r.battery_lives, r.battery_unstable, r.battery_sank, r.battery_cached);
  return 0;
}

}  // namespace plastivox::cli
