// Robustness to random stiffness (see robustness.hpp).
#include "plastivox/analysis/robustness.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "plastivox/analysis/rng.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/model.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::analysis {

const char* to_string(StiffnessDistribution d) {
  return d == StiffnessDistribution::kLinear ? "uniform" : "log-uniform";
}

RobotDef without_development(const RobotDef& robot) {
  RobotDef r = robot;
  std::fill(r.dev_rate.begin(), r.dev_rate.end(), 0.0);
  return r;
}

PhysicsDef robustness_physics(const PhysicsDef& physics) {
  PhysicsDef p = physics;
  p.treatment = Treatment::kNone;
  return p;
}

namespace {

struct Outcome {
  double fitness = 0;
  bool stable = false;
  std::string failure;
};

Outcome run(const RobotDef& robot, const PhysicsDef& physics, const Limits& limits) {
  SimResult r = simulate(compile(robot, physics, limits));
  judge_life(physics, r);  // as evolution judged the champion
  Outcome o;
  o.stable = r.status == SimStatus::kFinished;
  o.fitness = r.fitness;
  o.failure = o.stable ? "" : "simulation unstable: " + r.failure;
  return o;
}

// Draw k's stiffness field: one value per present voxel, increasing site order.
RobotDef random_stiffness(const RobotDef& reduced, const RobustnessOptions& o, double lo, double hi,
                          int k) {
  RobotDef r = reduced;
  Rng rng = Rng::stream(o.seed, StreamPurpose::kRobustness, static_cast<uint64_t>(k), 0);
  const double log_lo = std::log(lo), log_hi = std::log(hi);
  for (int s = 0; s < r.sites(); ++s) {
    if (!r.present[s]) continue;
    r.stiffness[s] = o.distribution == StiffnessDistribution::kLinear
                         ? rng.uniform(lo, hi)
                         : (lo == hi ? lo : std::exp(rng.uniform(log_lo, log_hi)));
  }
  return r;
}

// The stiffness range of the draws, checked.
void stiffness_range(const PhysicsDef& physics, const RobustnessOptions& options, double* lo,
                     double* hi) {
  const bool use_physics_range = options.e_lo == 0 && options.e_hi == 0;
  *lo = use_physics_range ? physics.e_min : options.e_lo;
  *hi = use_physics_range ? physics.e_max : options.e_hi;
  if (!std::isfinite(*lo) || !std::isfinite(*hi) || !(*lo > 0) || !(*hi >= *lo))
    throw std::invalid_argument("robustness: stiffness range must satisfy 0 < e_lo <= e_hi (got " +
                                std::to_string(*lo) + ", " + std::to_string(*hi) + ")");
}

}  // namespace

RobotDef robustness_draw(const RobotDef& champion, const PhysicsDef& physics,
                         const RobustnessOptions& options, int k) {
  validate(champion);
  if (k < 0) throw std::invalid_argument("robustness_draw: draw index must be >= 0");
  double lo = 0, hi = 0;
  stiffness_range(physics, options, &lo, &hi);
  return random_stiffness(without_development(champion), options, lo, hi, k);
}

RobustnessResult robustness(const RobotDef& champion, const PhysicsDef& physics,
                            const RobustnessOptions& options) {
  validate(champion);
  validate(physics);
  if (options.draws < 1) throw std::invalid_argument("robustness: draws must be >= 1");
  double lo = 0, hi = 0;
  stiffness_range(physics, options, &lo, &hi);

  const RobotDef reduced = without_development(champion);
  const PhysicsDef phys = robustness_physics(physics);

  // Item 0 is F_train; item k + 1 is draw k. Each writes only its own slot.
  std::vector<Outcome> outcomes(static_cast<size_t>(options.draws) + 1);
  parallel_for(static_cast<size_t>(options.draws + 1), options.threads, [&](size_t i_) {
    const int i = static_cast<int>(i_);
    outcomes[i] =
        i == 0 ? run(reduced, phys, options.limits)
               : run(random_stiffness(reduced, options, lo, hi, i - 1), phys, options.limits);
  });

  RobustnessResult res;
  res.distribution = to_string(options.distribution);
  res.e_lo = lo;
  res.e_hi = hi;
  res.seed = options.seed;
  res.f_train = outcomes[0].fitness;
  res.train_valid = outcomes[0].stable && outcomes[0].fitness > 0;
  res.train_failure = !outcomes[0].stable ? outcomes[0].failure
                      : !res.train_valid  ? "training fitness is 0: R is undefined"
                                          : "";
  double sum = 0;
  for (int k = 0; k < options.draws; ++k) {
    const Outcome& o = outcomes[k + 1];
    RobustnessDraw d;
    d.f_test = o.fitness;
    d.valid = o.stable && res.train_valid;
    d.failure = !o.stable ? o.failure : (!res.train_valid ? res.train_failure : "");
    if (d.valid) {
      d.r = o.fitness / res.f_train;
      sum += d.r;
      ++res.valid_draws;
    }
    res.draws.push_back(std::move(d));
  }
  res.mean_r = res.valid_draws > 0 ? sum / res.valid_draws : 0.0;
  return res;
}

}  // namespace plastivox::analysis
