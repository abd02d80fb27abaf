// The analysis for Python (python/plastivox/analysis.py): the measures `plastivox analyze` takes
// of every champion (robustness, canalization, Hausdorff diversity, body plans) and the bootstrap
// statistics it compares treatments with. Each call is the C++ function the study calls, with the
// arguments the study passes (plastivox/analysis/study.hpp, analysis/src/study/), so the same
// robot, stiffness and seeds give the same bits as analyze. The Python layer checks arguments;
// long calls (robustness, the Hausdorff matrix) release the GIL.
#include <algorithm>
#include <limits>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/analysis/battery.hpp"
#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/canalization.hpp"
#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/analysis/robustness.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/limits.hpp"

namespace plastivox::py {
namespace {

using Values = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>;

std::vector<double> values(const Values& a) {
  return {a.data(), a.data() + a.size()};
}

pyb::dict robustness_dict(const analysis::RobustnessResult& r) {
  std::vector<double> f_test, ratio;
  std::vector<uint8_t> valid;
  pyb::list failures;
  for (const analysis::RobustnessDraw& d : r.draws) {
    f_test.push_back(d.f_test);
    ratio.push_back(d.r);
    valid.push_back(d.valid ? 1 : 0);
    failures.append(d.failure);
  }
  pyb::dict out;
  out["distribution"] = r.distribution;
  out["e_lo"] = r.e_lo;
  out["e_hi"] = r.e_hi;
  out["seed"] = r.seed;
  out["f_train"] = r.f_train;
  out["train_valid"] = r.train_valid;
  out["train_failure"] = r.train_failure;
  out["f_test"] = to_array(f_test);
  out["r"] = to_array(ratio);
  out["valid"] = pyb::array_t<uint8_t>(static_cast<pyb::ssize_t>(valid.size()), valid.data());
  out["failures"] = failures;
  out["valid_draws"] = r.valid_draws;
  out["mean_r"] = r.mean_r;
  return out;
}

// Robots' robustness as the study measures its champions' (study_robustness.cpp): each robot
// under its physics, `draws` draws of `sampling` stiffness from its stream seed seeds[i];
// robots in parallel, each one's 1 + draws lives on the spare threads, as the study splits them
// (the numbers do not depend on it).
pyb::list robustness_of(const std::vector<const PyRobot*>& robots, const pyb::object& physics_arg,
                        const std::vector<uint64_t>& seeds, int draws, const std::string& sampling,
                        double e_lo, double e_hi, int threads) {
  if (seeds.size() != robots.size()) throw std::invalid_argument("seeds: one per robot");
  std::vector<PhysicsDef> physics;
  for (const PyRobot* r : robots)
    physics.push_back(physics_of_call(r->physics, physics_arg, std::nullopt, std::nullopt));
  std::vector<analysis::RobustnessResult> results(robots.size());
  {
    pyb::gil_scoped_release unlocked;
    const int all = threads > 0 ? threads : hardware_threads();
    const int outer = std::min(all, static_cast<int>(robots.size()));
    analysis::RobustnessOptions o;
    o.draws = draws;
    o.distribution = sampling == "log" ? analysis::StiffnessDistribution::kLogUniform
                                       : analysis::StiffnessDistribution::kLinear;
    o.e_lo = e_lo;
    o.e_hi = e_hi;
    o.threads = std::max(1, all / outer);
    o.limits = limits_from_environment();
    parallel_for(robots.size(), outer, [&](size_t i) {
      analysis::RobustnessOptions mine = o;
      mine.seed = seeds[i];
      results[i] = analysis::robustness(robots[i]->def, physics[i], mine);
    });
  }
  pyb::list out;
  for (const analysis::RobustnessResult& r : results) out.append(robustness_dict(r));
  return out;
}

// Robots' robustness profiles over a battery (battery.hpp), as the study runs them
// (study_battery.cpp): robot i from its stream seed seeds[i], robots in parallel, each one's
// lives on the spare threads. One row per life: columns as lists, for the Python layer.
pyb::list battery_of(const std::vector<const PyRobot*>& robots, const pyb::object& physics_arg,
                     const std::vector<uint64_t>& seeds, const std::string& spec, int paper_draws,
                     int threads) {
  if (seeds.size() != robots.size()) throw std::invalid_argument("seeds: one per robot");
  const analysis::Battery battery = analysis::load_battery(spec, paper_draws);
  std::vector<PhysicsDef> physics;
  for (const PyRobot* r : robots)
    physics.push_back(physics_of_call(r->physics, physics_arg, std::nullopt, std::nullopt));
  std::vector<analysis::RobustnessProfile> profiles(robots.size());
  {
    pyb::gil_scoped_release unlocked;
    const int all = threads > 0 ? threads : hardware_threads();
    const int outer = std::min(all, static_cast<int>(robots.size()));
    parallel_for(robots.size(), outer, [&](size_t i) {
      analysis::ProfileOptions o;
      o.seed = seeds[i];
      o.threads = std::max(1, all / outer);
      o.limits = limits_from_environment();
      profiles[i] = analysis::robustness_profile(robots[i]->def, physics[i], battery, o);
    });
  }
  pyb::list out;
  for (const analysis::RobustnessProfile& prof : profiles) {
    pyb::list perturbation, kind, unit, status, failure;
    std::vector<double> severity, fitness, kept, reference, mean, sd, auc;
    std::vector<uint64_t> seed;
    for (const analysis::PerturbationProfile& p : prof.perturbations)
      for (const analysis::SeverityLevel& l : p.levels)
        for (size_t k = 0; k < l.lives.size(); ++k) {
          const analysis::PerturbedOutcome& o = l.lives[k];
          const double nan = std::numeric_limits<double>::quiet_NaN();
          perturbation.append(p.name);
          kind.append(analysis::to_string(p.kind));
          unit.append(p.unit);
          status.append(o.status);
          failure.append(o.failure);
          severity.push_back(l.severity);
          seed.push_back(l.seeds[k]);
          fitness.push_back(o.status == "ok" || o.status == "no-reference" ? o.fitness : nan);
          kept.push_back(o.valid ? o.kept : nan);
          reference.push_back(p.reference_valid ? p.f_reference : nan);
          mean.push_back(l.mean_kept.value_or(nan));
          sd.push_back(l.sd_kept.value_or(nan));
          auc.push_back(p.auc.value_or(nan));
        }
    pyb::dict d;
    d["perturbation"] = perturbation;
    d["kind"] = kind;
    d["severity_unit"] = unit;
    d["status"] = status;
    d["failure"] = failure;
    d["severity"] = to_array(severity);
    d["seed"] = pyb::array_t<uint64_t>(static_cast<pyb::ssize_t>(seed.size()), seed.data());
    d["fitness"] = to_array(fitness);
    d["kept"] = to_array(kept);
    d["f_reference"] = to_array(reference);
    d["mean_kept"] = to_array(mean);
    d["sd_kept"] = to_array(sd);
    d["auc"] = to_array(auc);
    d["lives"] = prof.lives;
    d["unstable"] = prof.unstable;
    d["sank"] = prof.sank;
    out.append(d);
  }
  return out;
}

pyb::tuple hausdorff_matrix_of(const std::vector<const PyRobot*>& robots,
                               const std::string& rotations, const std::string& translation,
                               int threads) {
  std::vector<analysis::VoxelSet> sets;
  for (const PyRobot* r : robots) sets.push_back(analysis::voxel_set(r->def));
  analysis::HausdorffOptions ho;
  ho.rotations = analysis::parse_rotation_search(rotations);
  ho.translation = translation == "integer" ? analysis::TranslationSearch::kInteger
                                            : analysis::TranslationSearch::kNone;
  analysis::HausdorffMatrix m;
  {
    pyb::gil_scoped_release unlocked;
    m = analysis::hausdorff_matrix(sets, ho, threads);
  }
  const auto n = static_cast<pyb::ssize_t>(m.n), pairs = static_cast<pyb::ssize_t>(m.pairs.size());
  pyb::array_t<double> matrix({n, n});
  std::copy(m.distance.begin(), m.distance.end(), matrix.mutable_data());
  pyb::array_t<int> index(pairs), shift({pairs, pyb::ssize_t{3}});
  pyb::list names;
  for (pyb::ssize_t k = 0; k < pairs; ++k) {
    const analysis::HausdorffResult& p = m.pairs[k];
    index.mutable_at(k) = p.rotation_index;
    for (int a = 0; a < 3; ++a) shift.mutable_at(k, a) = p.translation[a];
    names.append(p.rotation.name);
  }
  return pyb::make_tuple(matrix, index, names, shift);
}

pyb::dict plan_match(const analysis::PlanMatch& p) {
  pyb::dict d;
  d["plan"] = analysis::to_string(p.plan);
  d["score"] = p.score;
  d["fill"] = p.fill;
  d["empty"] = p.empty;
  d["inside"] = p.inside;
  d["quarter_turns"] = p.quarter_turns;
  d["parameters"] = p.parameters;
  return d;
}

pyb::dict body_plan_of(const PyRobot& robot, double threshold) {
  analysis::BodyPlanOptions o;
  o.threshold = threshold;
  const analysis::BodyPlanResult r =
      analysis::classify_body_plan(analysis::voxel_set(robot.def), o);
  pyb::dict d;
  d["plan"] = analysis::to_string(r.plan);
  d["confidence"] = r.confidence;
  d["margin"] = r.margin;
  d["voxels"] = r.features.voxels;
  d["extent"] = pyb::make_tuple(r.features.extent[0], r.features.extent[1], r.features.extent[2]);
  d["box_fill"] = r.features.box_fill;
  d["footprint_components"] = r.features.footprint_components;
  pyb::list matches;
  for (const analysis::PlanMatch& m : r.features.matches) matches.append(plan_match(m));
  d["matches"] = matches;
  return d;
}

pyb::dict ci_dict(const analysis::ConfidenceInterval& c) {
  pyb::dict d;
  d["method"] = c.method;
  d["level"] = c.level;
  d["resamples"] = c.resamples;
  d["seed"] = c.seed;
  d["n"] = c.n;
  d["mean"] = c.mean;
  d["low"] = c.lower;
  d["high"] = c.upper;
  return d;
}

pyb::dict test_dict(const analysis::BootstrapTestResult& t) {
  pyb::dict d;
  d["test"] = t.test;
  d["null_model"] = t.null_model;
  d["correction"] = t.correction;
  d["comparisons"] = t.comparisons;
  d["level"] = t.level;
  d["resamples"] = t.resamples;
  d["seed"] = t.seed;
  d["a"] = t.name_a;
  d["b"] = t.name_b;
  d["n_a"] = t.n_a;
  d["n_b"] = t.n_b;
  d["mean_a"] = t.mean_a;
  d["mean_b"] = t.mean_b;
  d["difference"] = t.difference;
  d["p"] = t.p_value;
  d["p_corrected"] = t.p_corrected;
  d["significant"] = t.significant;
  d["stars"] = t.stars;
  d["cohens_d"] = t.effect.cohens_d;
  d["hedges_g"] = t.effect.hedges_g;
  d["pooled_sd"] = t.effect.pooled_sd;
  return d;
}

analysis::BootstrapTestOptions test_options(int resamples, uint64_t seed, const std::string& null,
                                            double level, int comparisons) {
  analysis::BootstrapTestOptions o;
  o.resamples = resamples;
  o.seed = seed;
  o.null_model = null == "shifted-means" ? analysis::BootstrapNull::kShiftedMeans
                                         : analysis::BootstrapNull::kPooled;
  o.level = level;
  o.comparisons = comparisons;
  return o;
}

// A results file's champion as the study loads it (study_load.cpp): the robot under the run's
// physics, its stored final stiffness (lattice-sized), its own evaluation and fitness.
pyb::tuple results_champion(const std::string& path, int generation) {
  const evo::ResultsFile rf = evo::read_results(path);
  const evo::RunState& run = rf.state;
  const evo::ChampionRecord& c = evo::champion_at(run, generation, path);
  PyRobot robot;
  robot.def = evo::champion_robot(c, generation < 0 ? run.generations_done : generation);
  robot.physics = run.config.physics;
  robot.source = path;
  return pyb::make_tuple(robot, to_array(c.final_stiffness),
                         evo::to_string(static_cast<evo::EvalStatus>(c.status)), c.fitness,
                         rf.content_digest);
}

}  // namespace

void bind_analysis(pyb::module_& m) {
  m.def("analysis_robustness", &robustness_of, pyb::arg("robots"), pyb::arg("physics"),
        pyb::arg("seeds"), pyb::arg("draws"), pyb::arg("sampling"), pyb::arg("e_lo"),
        pyb::arg("e_hi"), pyb::arg("threads"));
  m.def("analysis_battery", &battery_of, pyb::arg("robots"), pyb::arg("physics"), pyb::arg("seeds"),
        pyb::arg("battery"), pyb::arg("paper_draws"), pyb::arg("threads"));
  m.def("analysis_robustness_seed", [](uint64_t seed, const PyRobot& r) {
    return analysis::champion_robustness_seed(seed, r.def);
  });
  m.def("analysis_phenotype_digest",
        [](const PyRobot& r) { return analysis::phenotype_digest(r.def); });
  m.def("analysis_canalization", [](const Values& e0, const Values& e_final) {
    const analysis::Canalization c = analysis::canalization(values(e0), values(e_final));
    return pyb::make_tuple(c.m_body, c.v_body);
  });
  m.def("analysis_v_gain", [](const Values& alpha, double lo, double hi) {
    return analysis::v_gain(values(alpha), {lo, hi});
  });
  m.def("analysis_alpha_range", [](const std::vector<Values>& alphas) {
    std::vector<std::vector<double>> all;
    for (const Values& a : alphas) all.push_back(values(a));
    const analysis::AlphaRange r = analysis::evolved_alpha_range(all);
    return pyb::make_tuple(r.min, r.max);
  });
  m.def("analysis_hausdorff_matrix", &hausdorff_matrix_of);
  m.def("analysis_body_plan", &body_plan_of);
  m.def("analysis_bootstrap_ci", [](const Values& x, double level, int resamples, uint64_t seed) {
    return ci_dict(analysis::bootstrap_mean_ci(values(x), level, resamples, seed));
  });
  m.def("analysis_bootstrap_test",
        [](const Values& a, const Values& b, int resamples, uint64_t seed, const std::string& null,
           double level, int comparisons) {
          return test_dict(analysis::bootstrap_test(
              values(a), values(b), test_options(resamples, seed, null, level, comparisons)));
        });
  m.def("analysis_bootstrap_tests",
        [](const std::vector<std::string>& names, const std::vector<Values>& samples, int resamples,
           uint64_t seed, const std::string& null, double level, int comparisons) {
          std::vector<analysis::NamedSample> s;
          for (size_t i = 0; i < names.size(); ++i) s.push_back({names[i], values(samples.at(i))});
          pyb::list out;
          for (const analysis::BootstrapTestResult& t : analysis::pairwise_bootstrap_tests(
                   s, test_options(resamples, seed, null, level, comparisons)))
            out.append(test_dict(t));
          return out;
        });
  m.def("analysis_bonferroni", &analysis::bonferroni);
  m.def("analysis_mix64", [](uint64_t x) { return mix64(x); });
  m.def("analysis_panel_seed", &analysis::panel_seed);
  m.def("analysis_group_ci_seed", [](uint64_t panel_seed, const std::string& treatment) {
    return analysis::group_ci_seed(panel_seed, parse_treatment(treatment));
  });
  m.def("analysis_results_champion", &results_champion);
}

}  // namespace plastivox::py
