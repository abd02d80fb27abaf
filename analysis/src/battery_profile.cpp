// A champion's robustness profile over a battery (see battery.hpp): every life in one
// parallel loop, each writing only its own slot, so the profile is the same on any number of
// threads.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plastivox/analysis/battery.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/model.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::analysis {
namespace {

struct Job {
  int perturbation = -1;  // -1: a reference life
  int level = 0;
  uint64_t seed = 0;
  bool paper_reference = false;
};

bool needs_paper_reference(const Battery& b) {
  for (const Perturbation& p : b.perturbations)
    if (p.kind == PerturbationKind::kPaper) return true;
  return false;
}

bool needs_evolved_reference(const Battery& b) {
  for (const Perturbation& p : b.perturbations)
    if (p.kind != PerturbationKind::kPaper) return true;
  return false;
}

// The seeds one severity of p simulates: all of them when p draws, else the first.
std::vector<uint64_t> life_seeds(const Perturbation& p) {
  if (is_random(p.kind)) return p.seeds;
  return {p.seeds.front()};
}

std::vector<Job> jobs_of(const Battery& b) {
  std::vector<Job> jobs;
  if (needs_evolved_reference(b)) jobs.push_back({-1, 0, 0, false});
  if (needs_paper_reference(b)) jobs.push_back({-1, 0, 0, true});
  for (size_t i = 0; i < b.perturbations.size(); ++i) {
    const Perturbation& p = b.perturbations[i];
    for (size_t l = 0; l < p.severities.size(); ++l)
      for (uint64_t s : life_seeds(p))
        jobs.push_back({static_cast<int>(i), static_cast<int>(l), s, false});
  }
  return jobs;
}

// The robot and physics of every job, in jobs_of's order.
std::vector<PerturbedLife> lives_of(const RobotDef& champion, const PhysicsDef& physics,
                                    const Battery& battery, uint64_t base_seed) {
  std::vector<PerturbedLife> lives;
  for (const Job& job : jobs_of(battery)) {
    if (job.perturbation < 0) {
      lives.push_back(reference_life(
          champion, physics,
          job.paper_reference ? PerturbationKind::kPaper : PerturbationKind::kVoxelLoss));
      continue;
    }
    const Perturbation& p = battery.perturbations[job.perturbation];
    lives.push_back(
        perturb(champion, physics, p.kind, p.severities[job.level], job.seed, base_seed));
  }
  return lives;
}

// Mean and sample standard deviation of the valid lives, in seed order; the area under the
// curve by trapezoids over the severities, divided by their span.
void summarise(PerturbationProfile& p) {
  bool all_defined = true;
  for (SeverityLevel& l : p.levels) {
    double sum = 0;
    for (const PerturbedOutcome& o : l.lives)
      if (o.valid) sum += o.kept;
    if (l.valid == 0) {
      all_defined = false;
      continue;
    }
    l.mean_kept = sum / l.valid;
    if (l.valid >= 2) {
      double ss = 0;
      for (const PerturbedOutcome& o : l.lives)
        if (o.valid) ss += (o.kept - *l.mean_kept) * (o.kept - *l.mean_kept);
      l.sd_kept = std::sqrt(ss / (l.valid - 1));
    }
  }
  if (!all_defined) return;
  if (p.levels.size() == 1) {
    p.auc = p.levels[0].mean_kept;
    return;
  }
  double area = 0;
  for (size_t i = 1; i < p.levels.size(); ++i)
    area += (p.levels[i].severity - p.levels[i - 1].severity) *
            (*p.levels[i].mean_kept + *p.levels[i - 1].mean_kept) / 2;
  p.auc = area / (p.levels.back().severity - p.levels.front().severity);
}

}  // namespace

BatteryRun run_battery_life(const PerturbedLife& life, const Limits& limits) {
  SimResult r = simulate(compile(life.robot, life.physics, limits));
  judge_life(life.physics, r);  // a sunk life counts as evolution counts it (sinking_invalid)
  BatteryRun s;
  if (r.status == SimStatus::kFinished) {
    s.fitness = r.fitness;
    s.status = "ok";
  } else {
    s.status = r.sank ? "sank" : "unstable";
    s.failure = r.failure;
  }
  return s;
}

double life_voxel_steps(const PerturbedLife& life) {
  double e_top = 0;
  int voxels = 0;
  for (int s = 0; s < life.robot.sites(); ++s)
    if (life.robot.present[s]) {
      e_top = std::max(e_top, life.robot.stiffness[s]);
      ++voxels;
    }
  return voxels * life.physics.duration / time_step_at(life.physics, life.robot.voxel_size, e_top);
}

int battery_lives(const Battery& b) {
  return static_cast<int>(jobs_of(b).size());
}

double battery_voxel_steps(const RobotDef& champion, const PhysicsDef& physics,
                           const Battery& battery, uint64_t base_seed) {
  validate(battery, battery.name.empty() ? "battery" : battery.name);
  double total = 0;
  for (const PerturbedLife& life : lives_of(champion, physics, battery, base_seed))
    total += life_voxel_steps(life);
  return total;
}

std::vector<PerturbedLife> battery_lives_of(const RobotDef& champion, const PhysicsDef& physics,
                                            const Battery& battery, uint64_t base_seed,
                                            const Limits& limits) {
  validate(champion);
  validate(physics);
  validate(battery, battery.name.empty() ? "battery" : battery.name);
  std::vector<PerturbedLife> lives = lives_of(champion, physics, battery, base_seed);
  for (const PerturbedLife& life : lives) {
    validate(life.robot, limits);
    validate(life.physics);
  }
  return lives;
}

RobustnessProfile robustness_profile(const RobotDef& champion, const PhysicsDef& physics,
                                     const Battery& battery, const ProfileOptions& options) {
  // Every perturbed robot and physics is made (and checked) before any life is simulated.
  const std::vector<PerturbedLife> lives =
      battery_lives_of(champion, physics, battery, options.seed, options.limits);
  std::vector<BatteryRun> runs(lives.size());
  parallel_for(lives.size(), options.threads,
               [&](size_t j) { runs[j] = run_battery_life(lives[j], options.limits); });
  return assemble_profile(battery, options.seed, runs);
}

RobustnessProfile assemble_profile(const Battery& battery, uint64_t base_seed,
                                   const std::vector<BatteryRun>& sims) {
  const std::vector<Job> jobs = jobs_of(battery);
  if (sims.size() != jobs.size())
    throw std::invalid_argument("assemble_profile: " + std::to_string(sims.size()) +
                                " outcomes for a battery of " + std::to_string(jobs.size()) +
                                " lives");
  RobustnessProfile out;
  out.battery = battery.name;
  out.seed = base_seed;
  const BatteryRun* evolved_ref = nullptr;
  const BatteryRun* paper_ref = nullptr;
  for (size_t j = 0; j < jobs.size(); ++j)
    if (jobs[j].perturbation < 0) (jobs[j].paper_reference ? paper_ref : evolved_ref) = &sims[j];
  for (const Perturbation& p : battery.perturbations) {
    PerturbationProfile pp;
    pp.name = p.name;
    pp.kind = p.kind;
    pp.unit = severity_unit(p.kind);
    const BatteryRun& ref = *(p.kind == PerturbationKind::kPaper ? paper_ref : evolved_ref);
    pp.f_reference = ref.fitness;
    pp.reference_valid = ref.status == "ok" && ref.fitness > 0;
    pp.reference_failure =
        ref.status != "ok" ? ref.status + ": " + ref.failure
        : !pp.reference_valid
            ? "reference fitness is " + std::to_string(ref.fitness) + ": fitness kept is undefined"
            : "";
    for (double s : p.severities) pp.levels.push_back({s, life_seeds(p), {}, 0, 0, 0, {}, {}});
    out.perturbations.push_back(std::move(pp));
  }
  for (size_t j = 0; j < jobs.size(); ++j) {
    const Job& job = jobs[j];
    ++out.lives;
    if (sims[j].status == "unstable") ++out.unstable;
    if (sims[j].status == "sank") ++out.sank;
    if (job.perturbation < 0) continue;
    PerturbationProfile& pp = out.perturbations[job.perturbation];
    SeverityLevel& l = pp.levels[job.level];
    PerturbedOutcome o;
    o.status = sims[j].status;
    o.failure = sims[j].failure;
    if (o.status == "ok") {
      o.fitness = sims[j].fitness;
      if (pp.reference_valid) {
        o.valid = true;
        o.kept = o.fitness / pp.f_reference;
        ++l.valid;
      } else {
        o.status = "no-reference";
        o.failure = pp.reference_failure;
      }
    } else if (o.status == "sank") {
      ++l.sank;
    } else {
      ++l.unstable;
    }
    l.lives.push_back(std::move(o));
  }
  for (PerturbationProfile& pp : out.perturbations) summarise(pp);
  return out;
}

}  // namespace plastivox::analysis
