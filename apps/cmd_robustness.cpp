// plastivox robustness: the robustness battery (docs/analysis.md, "Robustness battery") on the
// run champions of several results files or on robot files (each under its own physics,
// optionally labelled TREATMENT=FILE), audited as analyze audits them: each
// champion's profile (fitness kept at every severity of every perturbation, its spread over seeds,
// the area under each curve) and the treatments compared per perturbation. Prints a table; --out
// DIR writes robustness.json and robustness.csv. The library call is battery_study
// (plastivox/analysis/study.hpp).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "battery_ranks.hpp"
#include "cli.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/evo/run.hpp"  // Cluster
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/panels.hpp"

namespace plastivox::cli {
namespace {

std::string shown(const std::optional<double>& x, const char* format = "%.3f") {
  if (!x) return "-";
  char b[32];
  std::snprintf(b, sizeof b, format, *x);
  return b;
}

void print_profiles(const analysis::StudyResult& r) {
  for (const analysis::ChampionAnalysis& c : r.champions) {
    if (!c.profile) {
      std::printf("%s: excluded (%s)\n", c.label.c_str(), c.artifact.c_str());
      continue;
    }
    std::printf("%s: %d lives, %d unstable, %d sank\n", c.label.c_str(), c.profile->lives,
                c.profile->unstable, c.profile->sank);
    for (const analysis::PerturbationProfile& p : c.profile->perturbations) {
      std::printf("  %-15s AUC %-6s", p.name.c_str(), shown(p.auc).c_str());
      if (!p.reference_valid) std::printf(" (%s)", p.reference_failure.c_str());
      for (const analysis::SeverityLevel& l : p.levels) {
        std::printf("  %g: %s", l.severity, shown(l.mean_kept).c_str());
        if (l.sd_kept) std::printf("±%s", shown(l.sd_kept).c_str());
        if (l.unstable + l.sank > 0)
          std::printf(" [%d of %zu failed]", l.unstable + l.sank, l.lives.size());
      }
      std::printf("\n");
    }
  }
}

void print_comparisons(const analysis::StudyResult& r) {
  if (r.treatments.size() < 2) return;
  std::printf("AUC by treatment (mean [95%% bootstrap CI]; Bonferroni-corrected tests):\n");
  for (const analysis::PanelStats& p : r.battery_panels) {
    std::printf("  %-15s", p.title.c_str());
    for (const analysis::GroupStats& g : p.groups) {
      std::printf("  %s %s", to_string(g.treatment), shown(g.mean).c_str());
      if (g.ci) std::printf(" [%.3f, %.3f]", g.ci->lower, g.ci->upper);
      std::printf(" n=%zu", g.values.size());
    }
    for (const analysis::BootstrapTestResult& t : p.comparisons)
      std::printf("  %s-%s p=%.3g%s", t.name_a.c_str(), t.name_b.c_str(), t.p_corrected,
                  t.stars.c_str());
    std::printf("\n");
  }
}

}  // namespace

int cmd_robustness(const Args& in) {
  Args args = in;
  analysis::StudyOptions o;
  o.battery = take_option(args, "--battery", "default");
  const std::string out = take_option(args, "--out", "");
  const std::string gen = take_option(args, "--generation", "last");
  if (gen != "last") o.generation = parse_count(gen, "--generation");
  o.seed = static_cast<uint64_t>(parse_count(take_option(args, "--seed", "1"), "--seed"));
  o.threads = parse_count(take_option(args, "--threads", "0"), "--threads");
  o.robustness_draws =
      parse_count(take_option(args, "--robustness-draws", "10"), "--robustness-draws");
  o.resamples = parse_count(take_option(args, "--resamples", "10000"), "--resamples");
  if (o.resamples < 100) throw UsageError{"--resamples expects at least 100"};
  if (o.robustness_draws < 1) throw UsageError{"--robustness-draws expects at least 1"};
  o.allow_mixed_physics = take_flag(args, "--allow-mixed-physics");
  o.keep_artifacts = take_flag(args, "--keep-artifacts");
  o.keep_vertical = take_flag(args, "--keep-vertical");
  const bool estimate_only = take_flag(args, "--estimate-only");
  reject_unknown_options(args);
  if (args.empty())
    throw UsageError{
        "expected results or robot files: plastivox robustness [TREATMENT=]FILE [...]"};
  // The battery is read and checked before any results file or life.
  const analysis::Battery battery = [&] {
    try {
      return analysis::load_battery(o.battery, o.robustness_draws);
    } catch (const std::invalid_argument& e) {
      throw InputError(e.what());
    }
  }();

  if (estimate_only) {
    const analysis::BatteryEstimate e = analysis::estimate_battery(args, o);
    std::printf(
        "battery %s: %d perturbations, %d lives per champion; %s: %d lives, %.3g voxel-steps; "
        "%.3g s per voxel-step (one life timed); predicted %.0f core-seconds, %.0f s on %s\n",
        battery.name.c_str(), static_cast<int>(battery.perturbations.size()),
        analysis::battery_lives(battery), count_of(e.champions, "champion").c_str(), e.lives,
        e.voxel_steps, e.seconds_per_voxel_step, e.core_seconds, e.seconds,
        count_of(e.threads, "thread").c_str());
    return 0;
  }
  o.command = "plastivox robustness";
  for (const std::string& a : in) o.command += " " + a;
  // Under mpirun every rank runs the same study and the battery's lives are shared among them
  // (battery_ranks.hpp); rank 0 alone talks and writes.
  const std::unique_ptr<evo::Cluster> mpi = join_mpi_job();
  const bool leader = !mpi || mpi->rank() == 0;
  o.battery_lives = battery_lives_over_ranks(mpi.get(), o.threads);
  const auto progress = [leader](const analysis::StudyProgress& p) {
    if (leader) std::fprintf(stderr, "plastivox robustness: %s\n", p.message.c_str());
  };
  analysis::StudyResult r;
  try {
    r = analysis::battery_study(args, o, progress);
  } catch (const std::exception& e) {
    abort_other_ranks(mpi.get(), "robustness", e);  // they would wait for ever
    throw;
  }
  if (!leader) return 0;
  print_profiles(r);
  print_comparisons(r);
  if (!out.empty()) {
    std::filesystem::create_directories(out);
    const std::string json = analysis::battery_stats_json(r);
    write_file_atomic(out + "/robustness.json", json);
    write_file_atomic(out + "/robustness.csv", analysis::battery_csv(r));
    // The heat map is drawn from the file just written, as plastivox figures draws stats.json.
    const render::BatteryHeatMap map =
        render::parse_battery_heat_map(nlohmann::json::parse(json), out + "/robustness.json", "");
    render::write_battery_heat_map(map, out, render::FigureOptions{});
    std::printf("wrote %s/{robustness.json, robustness.csv, robustness_heatmap.svg, .png}\n",
                out.c_str());
  }
  return 0;
}

}  // namespace plastivox::cli
