// Loading a study's inputs: one champion per results file, checked before anything runs.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "plastivox/base/hash.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/genome.hpp"  // kBodyPlanSeedCount
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {
namespace {

// One input before sorting.
struct Loaded {
  StudyInput input;
  ChampionAnalysis champion;
  std::string physics_without_treatment;  // resolved physics with treatment none
  // The config's identity (treatment and seed included) without the planned generations: two
  // files with equal replicate keys hold one evolutionary trajectory, however far each got.
  std::string replicate_key;
};

// The run's best and mean fitness and lineage count for generations 0..last.
EvolutionCurve evolution_curve(const evo::RunState& run, int last) {
  // The random individual each one descends from: parents are created before their children.
  std::vector<uint64_t> root(run.births.size());
  for (size_t i = 0; i < run.births.size(); ++i) {
    const int64_t parent = run.births[i].parent_id;
    root[i] = parent >= 0 && static_cast<size_t>(parent) < i ? root[parent] : i;
  }
  EvolutionCurve c;
  for (int g = 0; g <= last && g < static_cast<int>(run.history.size()); ++g) {
    const evo::GenerationRecord& h = run.history[g];
    double sum = 0;
    int valid = 0;
    std::vector<uint64_t> lineages;
    for (size_t k = 0; k < h.id.size(); ++k) {
      if (h.status[k] == static_cast<uint8_t>(evo::EvalStatus::kOk)) {
        sum += h.fitness[k];
        ++valid;
      }
      lineages.push_back(h.id[k] < root.size() ? root[h.id[k]] : h.id[k]);
    }
    std::sort(lineages.begin(), lineages.end());
    c.best.push_back(h.best_fitness);
    c.mean.push_back(valid ? sum / valid : std::nan(""));
    c.lineages.push_back(
        static_cast<int>(std::unique(lineages.begin(), lineages.end()) - lineages.begin()));
  }
  return c;
}

Loaded load_one(const std::string& file, const StudyOptions& options) {
  const evo::ResultsFile rf = evo::read_results(file);  // names the file when it refuses
  const evo::RunState& run = rf.state;
  if (run.generations_done < 0) throw std::runtime_error(file + ": no generation done yet");
  if (run.config.algorithm == evo::Algorithm::kCmaEs)  // its bodies were not evolved
    throw std::runtime_error(file + ": a " + to_string(run.config.algorithm) +
                             " run (one fixed body's " + to_string(run.config.cma.genome) +
                             " searched); the study compares afpo runs' evolved bodies and does "
                             "not read it");
  if (run.config.algorithm != evo::Algorithm::kAfpo)  // an archive, not a population
    throw std::runtime_error(file + ": a " + std::string(to_string(run.config.algorithm)) +
                             " run (an archive of elites); the study compares afpo runs' "
                             "evolved bodies and does not read it yet");
  int generation = run.generations_done;
  if (options.generation >= 0) {
    if (options.generation > run.generations_done)
      throw std::runtime_error(file + ": generation " + std::to_string(options.generation) +
                               " not reached (the run has " + std::to_string(run.generations_done) +
                               " generations done)");
    generation = options.generation;
  }
  // The champion at the end of `generation`: the last new best recorded by then.
  const evo::ChampionRecord* rec = nullptr;
  for (const evo::ChampionRecord& c : run.champions)
    if (c.generation <= generation) rec = &c;
  if (!rec)
    throw std::runtime_error(file + ": no champion recorded by generation " +
                             std::to_string(generation));

  Loaded l;
  l.input.file = file;
  l.input.content_digest = rf.content_digest;
  l.input.treatment = run.config.treatment;
  l.input.seed = run.config.seed;
  l.input.generation = generation;
  l.input.generations_done = run.generations_done;
  l.input.physics_json = evo::resolved_physics_json(run.config.physics);
  l.input.body_plan_start = run.config.initial_population == evo::InitialPopulation::kBodyPlans;
  l.input.evolution = evolution_curve(run, generation);
  PhysicsDef neutral = run.config.physics;
  neutral.treatment = Treatment::kNone;
  l.physics_without_treatment = evo::resolved_physics_json(neutral);
  nlohmann::json identity = nlohmann::json::parse(run.config.identity_json());
  identity.erase("generations");
  l.replicate_key = identity.dump();

  ChampionAnalysis& c = l.champion;
  c.treatment = run.config.treatment;
  c.run_seed = run.config.seed;
  c.generation = generation;
  c.id = rec->id;
  c.robot = rec->phenotype;
  c.final_stiffness = rec->final_stiffness;
  c.physics = run.config.physics;
  c.voxels = c.robot.voxel_count();
  if (c.voxels == 0)
    throw std::runtime_error(file + ": the champion at generation " + std::to_string(generation) +
                             " has no voxels");
  c.fitness = rec->fitness;
  c.evaluation = evo::to_string(static_cast<evo::EvalStatus>(rec->status));
  if (c.evaluation != "ok") {
    c.status = c.evaluation;
    c.status_detail = "the champion's own evaluation: " + c.evaluation;
    if (rec->id < run.births.size() && !run.births[rec->id].failure.empty())
      c.status_detail += " (" + run.births[rec->id].failure + ")";
    for (const char* m : {"fitness", "m_body", "v_body"}) c.undefined[m] = c.status_detail;
  }
  c.phenotype_digest = phenotype_digest(c.robot);
  if (l.input.body_plan_start) {  // generation 0's first newcomers, ids 0, 1, 2, were the plans
    uint64_t root = rec->id;
    while (root < run.births.size() && run.births[root].parent_id >= 0 &&
           static_cast<uint64_t>(run.births[root].parent_id) < root)
      root = static_cast<uint64_t>(run.births[root].parent_id);
    if (root < static_cast<uint64_t>(evo::kBodyPlanSeedCount) && root < run.births.size() &&
        run.births[root].generation == 0)
      c.seeded_plan = static_cast<int>(root);
  }
  return l;
}

std::string join_treatments(const std::vector<Treatment>& ts) {
  std::string s;
  for (Treatment t : ts) s += (s.empty() ? "" : ", ") + std::string(to_string(t));
  return s;
}

void check_treatments(const std::vector<Loaded>& all, const StudyOptions& options) {
  const auto& expected = options.treatments;
  if (!expected.empty()) {
    for (const Loaded& l : all)
      if (std::find(expected.begin(), expected.end(), l.input.treatment) == expected.end())
        throw std::runtime_error(l.input.file + ": treatment " + to_string(l.input.treatment) +
                                 " is not among the expected treatments (" +
                                 join_treatments(expected) + ")");
    for (Treatment t : expected)
      if (std::none_of(all.begin(), all.end(),
                       [&](const Loaded& l) { return l.input.treatment == t; }))
        throw std::runtime_error(std::string("treatment ") + to_string(t) +
                                 ": no results file given (empty treatment)");
  }
  // Every treatment needs at least one champion whose own evaluation is valid.
  std::map<Treatment, std::string> files;
  std::map<Treatment, bool> usable;
  for (const Loaded& l : all) {
    files[l.input.treatment] += (files[l.input.treatment].empty() ? "" : ", ") + l.input.file;
    usable[l.input.treatment] = usable[l.input.treatment] || l.champion.evaluation == "ok";
  }
  for (const auto& [t, ok] : usable)
    if (!ok)
      throw std::runtime_error(std::string("treatment ") + to_string(t) +
                               ": no champion with a valid evaluation (" + files[t] + ")");
}

}  // namespace

void load_champions(const std::vector<std::string>& files, const StudyOptions& options,
                    StudyResult& out) {
  if (files.empty()) throw std::runtime_error("no results files given");
  std::vector<Loaded> all;
  for (const std::string& f : files) all.push_back(load_one(f, options));

  // File order must not matter: sort by treatment, run seed, content digest.
  std::sort(all.begin(), all.end(), [](const Loaded& a, const Loaded& b) {
    return std::tie(a.input.treatment, a.input.seed, a.input.content_digest) <
           std::tie(b.input.treatment, b.input.seed, b.input.content_digest);
  });
  for (size_t i = 1; i < all.size(); ++i)
    if (all[i].input.content_digest == all[i - 1].input.content_digest)
      throw std::runtime_error(all[i].input.file + ": the same run as " + all[i - 1].input.file +
                               " (content digest " + all[i].input.content_digest + ")");
  // Pseudo-replication: two files of the same config and seed (say a finished run and an
  // unfinished copy of it) are one replicate, not two independent ones.
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j)
      if (all[i].replicate_key == all[j].replicate_key) {
        Hasher h;
        h.str(all[i].replicate_key);
        const auto done = [](const Loaded& l) {
          return std::to_string(l.input.generations_done) + " generations done";
        };
        throw std::runtime_error(
            all[i].input.file + " and " + all[j].input.file + " are the same run (treatment " +
            to_string(all[i].input.treatment) + ", seed " + std::to_string(all[i].input.seed) +
            ", config digest " + h.finish().hex().substr(0, 12) + "; " + done(all[i]) + " and " +
            done(all[j]) + "), not two replicates: analyse one");
      }
  check_treatments(all, options);

  // Physics: every run must have been simulated alike, apart from the treatment.
  for (size_t i = 1; i < all.size(); ++i) {
    if (all[i].physics_without_treatment == all[0].physics_without_treatment) continue;
    const std::string what =
        "mixed physics: " + all[0].input.file + " and " + all[i].input.file +
        " were simulated with different physics (" +
        first_difference(nlohmann::json::parse(all[0].physics_without_treatment),
                         nlohmann::json::parse(all[i].physics_without_treatment),
                         "in " + all[0].input.file, "in " + all[i].input.file) +
        ")";
    if (!options.allow_mixed_physics)
      throw std::runtime_error(what + "; pass --allow-mixed-physics to analyse them anyway");
    out.warnings.push_back(what + "; each champion is re-simulated with its own run's physics");
  }

  // Champions taken at different generations (each file's last, and the files got to
  // different generations) are compared across unequal amounts of evolution.
  if (options.generation < 0) {
    const auto [lo, hi] = std::minmax_element(
        all.begin(), all.end(),
        [](const Loaded& a, const Loaded& b) { return a.input.generation < b.input.generation; });
    if (lo->input.generation != hi->input.generation)
      out.warnings.push_back(
          "the runs reached different generations (" + lo->input.file + ": " +
          std::to_string(lo->input.generation) + ", " + hi->input.file + ": " +
          std::to_string(hi->input.generation) +
          "), so their last champions had unequal evolution; pass --generation " +
          std::to_string(lo->input.generation) + " to compare them at one generation");
  }

  // Labels "<treatment>-s<seed>", made unique with "-r2", "-r3", ... in sorted order.
  std::map<std::string, int> seen;
  for (size_t i = 0; i < all.size(); ++i) {
    ChampionAnalysis& c = all[i].champion;
    c.label = std::string(to_string(c.treatment)) + "-s" + std::to_string(c.run_seed);
    const int k = ++seen[c.label];
    if (k > 1) c.label += "-r" + std::to_string(k);
    c.input = static_cast<int>(i);
    out.inputs.push_back(all[i].input);
    out.champions.push_back(std::move(c));
    if (std::find(out.treatments.begin(), out.treatments.end(), all[i].input.treatment) ==
        out.treatments.end())
      out.treatments.push_back(all[i].input.treatment);
  }
}

}  // namespace plastivox::analysis::study

namespace plastivox::analysis {

std::string phenotype_digest(const RobotDef& robot) {
  Hasher h;
  evo::hash_robot(h, robot);  // the evolver's phenotype hash
  return h.finish().hex();
}

void load_champion_bodies(StudyResult& r) {
  for (ChampionAnalysis& c : r.champions) {
    const StudyInput& in = r.inputs.at(static_cast<size_t>(c.input));
    StudyOptions o = r.options;
    o.generation = in.generation;
    const study::Loaded l = study::load_one(in.file, o);
    if (l.input.content_digest != in.content_digest)
      throw std::runtime_error(in.file + ": not the run analysed (content digest " +
                               l.input.content_digest + ", the analysis read " + in.content_digest +
                               ")");
    c.robot = l.champion.robot;
    c.final_stiffness = l.champion.final_stiffness;
    c.physics = l.champion.physics;
    c.fitness = l.champion.fitness;
    c.seeded_plan = l.champion.seeded_plan;
  }
  if (r.controller.empty()) r.controller = study::controller_of(r.champions);  // an older file
}

}  // namespace plastivox::analysis
