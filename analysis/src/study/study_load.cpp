// Loading a study's inputs: one champion per results file, checked before anything runs.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "plastivox/base/hash.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/evolver.hpp"  // evaluate_phenotype
#include "plastivox/evo/genome.hpp"   // kBodyPlanSeedCount
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/resolve_physics.hpp"
#include "plastivox/io/robot_io.hpp"
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
  bool robot_file = false;  // a robot file (.json, .vxa), not a results file
  std::string sort_name;    // a robot file's label (its file name); "" for a results file
};

// One input as given: "FILE" or "TREATMENT=FILE" (a treatment label; a path that exists as
// given is a file, '=' and all).
struct InputSpec {
  std::string path;
  std::optional<Treatment> label;
};

InputSpec parse_input(const std::string& arg) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || std::filesystem::exists(arg)) return {arg, std::nullopt};
  const std::string name = arg.substr(0, eq), path = arg.substr(eq + 1);
  std::string names;
  for (Treatment t : all_treatments())
    names += (names.empty() ? "" : ", ") + std::string(to_string(t));
  Treatment t{};
  try {
    t = parse_treatment(name);
  } catch (const std::exception&) {
    throw std::runtime_error(arg + ": '" + name +
                             "' is not a treatment (a label is TREATMENT=FILE, TREATMENT one of " +
                             names + ")");
  }
  if (path.empty()) throw std::runtime_error(arg + ": no file after the treatment label");
  return {path, t};
}

// Whether the study reads a results file of this algorithm: every algorithm's champion is a
// body with its fitness under the run's physics. The one place an algorithm is admitted or
// refused; the switch has no default, so a new algorithm must be decided here to compile.
void check_algorithm_readable(const evo::RunState& run, const std::string& file) {
  switch (run.config.algorithm) {
    case evo::Algorithm::kAfpo:       // evolved bodies
    case evo::Algorithm::kCmaEs:      // one fixed body with searched genes, rebuilt in its record
    case evo::Algorithm::kMapElites:  // the best elite; the curve's best is the archive's best
      return;
  }
  throw std::runtime_error(file + ": a results file of an algorithm the study does not read");
}

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

Loaded load_results(const std::string& file, const std::optional<Treatment>& label,
                    const StudyOptions& options) {
  const evo::ResultsFile rf = evo::read_results(file);  // names the file when it refuses
  const evo::RunState& run = rf.state;
  if (run.generations_done < 0) throw std::runtime_error(file + ": no generation done yet");
  check_algorithm_readable(run, file);
  if (label && *label != run.config.treatment)
    throw std::runtime_error(std::string(to_string(*label)) + "=" + file +
                             ": the run's treatment is " + to_string(run.config.treatment) +
                             ", not " + to_string(*label) +
                             " (a results file's treatment is its config's)");
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

// A robot file (.json, .vxa; docs/robot-format.md): its physics resolved by resolve_physics
// (the file's own, the label's treatment over it), its fitness and final stiffness simulated
// later (evaluate_robot_files), as evolution would have scored it.
Loaded load_robot_input(const std::string& file, const std::optional<Treatment>& label) {
  LoadedRobot loaded = load_robot(file);  // InputError naming the file and field
  PhysicsRequest req;
  req.where = file;
  req.treatment = label;
  const PhysicsDef physics = resolve_physics(loaded.physics, req);
  std::ifstream in(file, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  Hasher h;
  h.str("plastivox-study-robot-file-v1");
  h.str(bytes.str());
  h.str(evo::resolved_physics_json(physics));  // a label makes another input of the same bytes

  Loaded l;
  l.robot_file = true;
  l.sort_name = std::filesystem::path(file).stem().string();
  l.input.file = file;
  l.input.content_digest = h.finish().hex();
  l.input.treatment = physics.treatment;
  l.input.generation = -1;
  l.input.generations_done = -1;
  l.input.physics_json = evo::resolved_physics_json(physics);
  PhysicsDef neutral = physics;
  neutral.treatment = Treatment::kNone;
  l.physics_without_treatment = evo::resolved_physics_json(neutral);
  l.replicate_key = "robot file " + l.input.content_digest;

  ChampionAnalysis& c = l.champion;
  c.treatment = physics.treatment;
  c.generation = -1;
  c.robot = std::move(loaded.robot);
  c.physics = physics;
  c.voxels = c.robot.voxel_count();
  if (c.voxels == 0) throw std::runtime_error(file + ": the robot has no voxels");
  c.phenotype_digest = phenotype_digest(c.robot);
  return l;
}

// A robot file's own life, as evolution scores a body (evaluate_phenotype): its fitness, status
// and final stiffness, which a results file records beside its champion.
void evaluate_robot_file(Loaded& l) {
  ChampionAnalysis& c = l.champion;
  evo::Phenotype p;
  p.robot = c.robot;
  p.valid = true;
  p.voxels = c.voxels;
  const evo::Evaluation e = evo::evaluate_phenotype(p, c.physics);
  c.fitness = e.fitness;
  c.final_stiffness = e.final_stiffness;
  c.evaluation = evo::to_string(e.status);
  if (c.evaluation != "ok") {
    c.status = c.evaluation;
    c.status_detail = "the robot's own life: " + c.evaluation + " (" + e.failure + ")";
    for (const char* m : {"fitness", "m_body", "v_body"}) c.undefined[m] = c.status_detail;
  }
}

// One input as given ("FILE" or "TREATMENT=FILE"): a results file (.h5) or a robot file.
Loaded load_one(const std::string& arg, const StudyOptions& options) {
  const InputSpec spec = parse_input(arg);
  if (spec.path.size() > 3 && spec.path.substr(spec.path.size() - 3) == ".h5")
    return load_results(spec.path, spec.label, options);
  return load_robot_input(spec.path, spec.label);
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
    // A robot file not scored (an estimate) is not known to be unusable.
    const bool unscored = l.robot_file && l.champion.evaluation.empty();
    usable[l.input.treatment] =
        usable[l.input.treatment] || l.champion.evaluation == "ok" || unscored;
  }
  for (const auto& [t, ok] : usable)
    if (!ok)
      throw std::runtime_error(std::string("treatment ") + to_string(t) +
                               ": no champion with a valid evaluation (" + files[t] + ")");
}

}  // namespace

void load_champions(const std::vector<std::string>& files, const StudyOptions& options,
                    StudyResult& out, bool score_robot_files) {
  if (files.empty()) throw std::runtime_error("no results files given");
  std::vector<Loaded> all;
  for (const std::string& f : files) all.push_back(load_one(f, options));
  // Robot files are scored as evolution scored its champions, in parallel.
  std::vector<Loaded*> robots;
  for (Loaded& l : all)
    if (l.robot_file && score_robot_files) robots.push_back(&l);
  const int threads = options.threads > 0 ? options.threads : hardware_threads();
  parallel_for(robots.size(), threads, [&](size_t i) { evaluate_robot_file(*robots[i]); });

  // File order must not matter: sort by treatment, run seed (none for a robot file), a robot
  // file's name, content digest.
  std::sort(all.begin(), all.end(), [](const Loaded& a, const Loaded& b) {
    return std::tie(a.input.treatment, a.input.seed, a.sort_name, a.input.content_digest) <
           std::tie(b.input.treatment, b.input.seed, b.sort_name, b.input.content_digest);
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
  std::vector<const Loaded*> runs;  // results files: robot files have no generation
  for (const Loaded& l : all)
    if (!l.robot_file) runs.push_back(&l);
  if (options.generation < 0 && !runs.empty()) {
    const auto [lo_it, hi_it] = std::minmax_element(
        runs.begin(), runs.end(),
        [](const Loaded* a, const Loaded* b) { return a->input.generation < b->input.generation; });
    const Loaded* lo = *lo_it;
    const Loaded* hi = *hi_it;
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
    c.label = all[i].robot_file
                  ? all[i].sort_name
                  : std::string(to_string(c.treatment)) + "-s" + std::to_string(c.run_seed);
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
    const bool robot_file = !(in.file.size() > 3 && in.file.substr(in.file.size() - 3) == ".h5");
    // A robot file is read again under the treatment it was analysed with (its label's).
    study::Loaded l = study::load_one(
        robot_file ? std::string(to_string(in.treatment)) + "=" + in.file : in.file, o);
    if (robot_file) study::evaluate_robot_file(l);
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
