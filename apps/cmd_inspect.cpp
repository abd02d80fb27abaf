// plastivox inspect: summarise an evolution results file (text or JSON).
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/task.hpp"

namespace plastivox::cli {

int cmd_inspect(const Args& in) {
  Args args = in;
  const bool as_json = take_flag(args, "--json");
  reject_unknown_options(args);
  if (args.size() != 1) throw UsageError{"expected one results file"};
  const std::string path = args[0];
  const evo::ResultsFile f = evo::read_results(path);
  const evo::RunState& s = f.state;
  const evo::GenerationRecord& last = s.history.back();
  const evo::ChampionRecord& champ = s.champions.back();
  // Whether the champion meets its task's criterion, where the file can tell: a least fitness
  // (every task but climb). Climb's criterion reads the ground under the centre of mass at
  // the end of the life, which the file does not keep: null, and the text says how to check.
  const TaskInfo& task = task_info(s.config.task);
  const bool decidable = task.succeeds == nullptr;
  // Whether the champion's life scored by rising or falling (docs/evolution.md, "Flagged
  // lives"): crowned only when no life of the run counted (false in files written before the
  // flag, which did not look).
  const bool vertical = champ.id < s.births.size() && s.births[champ.id].vertical != 0;
  const bool success = decidable && !vertical &&
                       static_cast<evo::EvalStatus>(champ.status) == evo::EvalStatus::kOk &&
                       last.best_fitness >= task.threshold;
  int64_t simulations = 0;
  for (const evo::GenerationRecord& g : s.history) simulations += g.simulated;

  nlohmann::json j;
  j["file"] = path;
  j["format_version"] = evo::kResultsFormatVersion;
  j["treatment"] = to_string(s.config.treatment);
  j["task"] = to_string(s.config.task);
  j["fitness_unit"] = task_info(s.config.task).unit;
  j["seed"] = s.config.seed;
  j["algorithm"] = to_string(s.config.algorithm);
  if (s.config.algorithm == evo::Algorithm::kCmaEs) {
    j["genome"] = to_string(s.config.cma.genome);
    j["genome_dimension"] = s.config.controller_genes.count;
    j["covariance"] = s.config.cma.separable ? "separable" : "full";
    j["step_size"] = s.cma.sigma;
  }
  if (s.config.algorithm == evo::Algorithm::kMapElites) {  // the archive (champion: best elite)
    const evo::MapElitesSettings& me = s.config.map_elites;
    nlohmann::json axes = nlohmann::json::array();
    for (const evo::DescriptorAxis& a : me.axes)
      axes.push_back({{"name", to_string(a.what)}, {"bounds", {a.lo, a.hi}}, {"bins", a.bins}});
    j["descriptors"] = axes;
    j["cells"] = me.cells();
    j["filled"] = s.archive.size();
    j["coverage"] = static_cast<double>(s.archive.size()) / static_cast<double>(me.cells());
    j["qd_score"] = s.history.empty() ? 0.0 : s.history.back().qd_score;
    j["qd_offset"] = me.qd_offset;
  }
  j["population"] = s.config.population;
  j["generations_planned"] = s.config.generations;
  j["generations_done"] = s.generations_done;
  j["finished"] = s.finished();
  j["best_fitness"] = last.best_fitness;
  j["champion_id"] = last.champion_id;
  // The generation at whose end the champion first became the best (the results file's
  // /champion attribute `generation`); it is still the champion at generations_done, the
  // generation export and Results.champion() name it by.
  j["champion_since_generation"] = champ.generation;
  j["champion_voxels"] = champ.phenotype.voxel_count();
  j["champion_status"] = to_string(static_cast<evo::EvalStatus>(champ.status));
  j["champion_vertical"] = vertical;
  j["champion_success"] = decidable ? nlohmann::json(success) : nlohmann::json(nullptr);
  j["individuals"] = s.births.size();
  j["simulations"] = simulations;
  j["content_digest"] = f.content_digest;
  for_each_field(f.provenance, [&](const char* name, const auto& v) { j[name] = v; });
  if (as_json) {
    std::printf("%s\n", j.dump(1).c_str());
    return 0;
  }
  std::printf("%s: treatment %s, task %s, seed %llu, %d/%d generations%s\n", path.c_str(),
              to_string(s.config.treatment), to_string(s.config.task),
              static_cast<unsigned long long>(s.config.seed), s.generations_done,
              s.config.generations, s.finished() ? " (finished)" : "");
  if (s.config.algorithm == evo::Algorithm::kCmaEs)
    std::printf(
        "  cma-es on the body's %s (%d numbers, %s covariance, %d samples a generation), "
        "step size now %.4g\n",
        to_string(s.config.cma.genome), s.config.controller_genes.count,
        s.config.cma.separable ? "separable" : "full", s.config.population, s.cma.sigma);
  if (s.config.algorithm == evo::Algorithm::kMapElites)
    std::printf(
        "  map-elites archive: %zu of %lld cells filled (coverage %.4f), QD score %.6g "
        "(fitness - %g summed over them), %d children a generation\n",
        s.archive.size(), static_cast<long long>(s.config.map_elites.cells()),
        static_cast<double>(s.archive.size()) / static_cast<double>(s.config.map_elites.cells()),
        s.history.empty() ? 0.0 : s.history.back().qd_score, s.config.map_elites.qd_offset,
        s.config.population);
  std::printf("  best fitness %.6f %s: champion id %llu (%d voxels, since generation %d)\n",
              last.best_fitness, task_info(s.config.task).unit,
              static_cast<unsigned long long>(last.champion_id), champ.phenotype.voxel_count(),
              champ.generation);
  if (vertical)
    std::printf(
        "  the champion scored by rising or falling, as no life of the run counted "
        "(docs/evolution.md, \"Flagged lives\")\n");
  std::printf("  %s: %s\n",
              !decidable ? "success unknown (export the champion and simulate it)"
              : success  ? "success"
                         : "no success",
              task.criterion);
  std::printf("  %zu individuals, %lld simulated; content digest %s\n", s.births.size(),
              static_cast<long long>(simulations), f.content_digest.c_str());
  std::printf("  written by plastivox %s (commit %s) on %s, %s\n",
              f.provenance.plastivox_version.c_str(), f.provenance.git_commit.c_str(),
              f.provenance.host.c_str(), f.provenance.date_updated.c_str());
  return 0;
}

}  // namespace plastivox::cli
