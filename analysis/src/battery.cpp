// The robustness battery's perturbations and built-in batteries (see battery.hpp).
#include "plastivox/analysis/battery.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>

#include "plastivox/analysis/rng.hpp"
#include "plastivox/analysis/robustness.hpp"

namespace plastivox::analysis {
namespace {

struct KindInfo {
  PerturbationKind kind;
  const char* name;
  const char* unit;
  SeverityRange range;
  bool random;
};

const KindInfo kKinds[] = {
    {PerturbationKind::kPaper, "paper", "share of the log stiffness range", {0, 1, true}, true},
    {PerturbationKind::kVoxelLoss, "voxel-loss", "share of voxels", {0, 0.9, false}, true},
    {PerturbationKind::kLimbLoss, "limb-loss", "share of the body's extent", {0, 0.9, false}, true},
    {PerturbationKind::kPhaseNoise, "phase-noise", "cycles", {0, 1, false}, true},
    {PerturbationKind::kAmplitudeLoss,
     "amplitude-loss",
     "share of amplitude",
     {0, 1, false},
     false},
    {PerturbationKind::kFriction, "friction", "x friction coefficients", {0, 10, true}, false},
    {PerturbationKind::kRoughGround, "rough-ground", "voxel lengths", {0, 5, false}, true},
    {PerturbationKind::kPayload, "payload", "x body weight", {0, 5, false}, false},
    {PerturbationKind::kGravity, "gravity", "x gravity", {0, 5, true}, false},
    {PerturbationKind::kBondModel, "bond-model", "1 = the other bond model", {1, 1, false}, false},
    {PerturbationKind::kTimeStep, "time-step", "x dt_frac", {0, 1, true}, false},
};

const KindInfo& info(PerturbationKind k) {
  for (const KindInfo& i : kKinds)
    if (i.kind == k) return i;
  throw std::logic_error("unknown perturbation kind");
}

bool in_range(PerturbationKind k, double s) {
  const SeverityRange r = severity_range(k);
  return std::isfinite(s) && (r.lo_open ? s > r.lo : s >= r.lo) && s <= r.hi;
}

std::string range_text(PerturbationKind k) {
  const SeverityRange r = severity_range(k);
  auto num = [](double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    return std::string(b);
  };
  return std::string(r.lo_open ? "(" : "[") + num(r.lo) + ", " + num(r.hi) + "]";
}

// The largest face-connected piece of the body (ties: the one holding the lowest site); every
// other voxel becomes absent. Only `present` changes (and boundary conditions on removed sites
// are dropped), so the kept voxels keep every other field bit for bit.
void keep_largest_piece(RobotDef& r) {
  const int n = r.sites();
  std::vector<int> piece(n, -1), sizes, stack;
  for (int s = 0; s < n; ++s) {
    if (!r.present[s] || piece[s] >= 0) continue;
    const int id = static_cast<int>(sizes.size());
    int size = 0;
    stack.assign(1, s);
    piece[s] = id;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      ++size;
      const int x = v % r.nx, y = (v / r.nx) % r.ny, z = v / (r.nx * r.ny);
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                            {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= r.nx || q[1] >= r.ny || q[2] >= r.nz)
          continue;
        const int w = r.site(q[0], q[1], q[2]);
        if (r.present[w] && piece[w] < 0) {
          piece[w] = id;
          stack.push_back(w);
        }
      }
    }
    sizes.push_back(size);
  }
  const int best = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  for (int s = 0; s < n; ++s)
    if (r.present[s] && piece[s] != best) r.present[s] = 0;
  auto gone = [&](int site) { return site < 0 || site >= n || !r.present[site]; };
  r.fixed_sites.erase(std::remove_if(r.fixed_sites.begin(), r.fixed_sites.end(), gone),
                      r.fixed_sites.end());
  r.loads.erase(std::remove_if(r.loads.begin(), r.loads.end(),
                               [&](const RobotDef::Load& l) { return gone(l.site); }),
                r.loads.end());
}

std::vector<int> present_sites(const RobotDef& r) {
  std::vector<int> out;
  for (int s = 0; s < r.sites(); ++s)
    if (r.present[s]) out.push_back(s);
  return out;
}

// Removes round(share * n) voxels chosen at random (at most n - 1), then keeps the largest piece.
void remove_voxels(RobotDef& r, double share, Rng& rng) {
  std::vector<int> sites = present_sites(r);
  const int n = static_cast<int>(sites.size());
  const int k = std::min(n - 1, static_cast<int>(std::lround(share * n)));
  for (int i = 0; i < k; ++i) {  // partial Fisher-Yates: sites[0..k) are the removed ones
    const int j = i + rng.index(n - i);
    std::swap(sites[i], sites[j]);
    r.present[sites[i]] = 0;
  }
  keep_largest_piece(r);
}

// Cuts off the body's end along one of +x, -x, +y, -y (drawn): the voxels in the last
// round(share * extent) layers of the body's extent that way (at most extent - 1), then keeps
// the largest piece.
void remove_limb(RobotDef& r, double share, Rng& rng) {
  const int dir = rng.index(4);  // 0 +x, 1 -x, 2 +y, 3 -y
  const bool along_x = dir < 2;
  int lo = INT_MAX, hi = INT_MIN;
  for (int s : present_sites(r)) {
    const int c = along_x ? s % r.nx : (s / r.nx) % r.ny;
    lo = std::min(lo, c);
    hi = std::max(hi, c);
  }
  const int extent = hi - lo + 1;
  const int cut = std::min(extent - 1, static_cast<int>(std::lround(share * extent)));
  if (cut <= 0) return;
  for (int s : present_sites(r)) {
    const int c = along_x ? s % r.nx : (s / r.nx) % r.ny;
    const bool positive_end = dir % 2 == 0;
    if (positive_end ? c > hi - cut : c < lo + cut) r.present[s] = 0;
  }
  keep_largest_piece(r);
}

// The stiffness range of `paper` at spread s: [e_min, e_max] at s = 1 (Eq. 2 exactly), else
// shrunk on a log scale about its geometric centre to the share s of its log width.
void paper_range(const PhysicsDef& p, double s, double* lo, double* hi) {
  if (s == 1) {
    *lo = p.e_min;
    *hi = p.e_max;
    return;
  }
  const double c = std::sqrt(p.e_min * p.e_max);
  *lo = c * std::pow(p.e_min / c, s);
  *hi = c * std::pow(p.e_max / c, s);
}

}  // namespace

const char* to_string(PerturbationKind k) {
  return info(k).name;
}

PerturbationKind parse_perturbation_kind(const std::string& name) {
  for (const KindInfo& i : kKinds)
    if (name == i.name) return i.kind;
  throw std::invalid_argument("unknown perturbation '" + name + "' (expected one of " +
                              perturbation_kind_names() + ")");
}

std::string perturbation_kind_names() {
  std::string out;
  for (const KindInfo& i : kKinds) out += (out.empty() ? "" : ", ") + std::string(i.name);
  return out;
}

const char* severity_unit(PerturbationKind k) {
  return info(k).unit;
}

SeverityRange severity_range(PerturbationKind k) {
  return info(k).range;
}

bool is_random(PerturbationKind k) {
  return info(k).random;
}

void validate(const Battery& b, const std::string& where) {
  if (b.perturbations.empty())
    throw std::invalid_argument(where + ": perturbations: the battery has no perturbation");
  for (size_t i = 0; i < b.perturbations.size(); ++i) {
    const Perturbation& p = b.perturbations[i];
    const std::string at = where + ": perturbations[" + std::to_string(i) + "].";
    if (p.name.empty()) throw std::invalid_argument(at + "name: must not be empty");
    for (size_t j = 0; j < i; ++j)
      if (b.perturbations[j].name == p.name)
        throw std::invalid_argument(at + "name: '" + p.name + "' appears twice");
    if (p.severities.empty())
      throw std::invalid_argument(at + "severities: at least one severity is needed");
    for (size_t k = 0; k < p.severities.size(); ++k) {
      if (!in_range(p.kind, p.severities[k]))
        throw std::invalid_argument(at + "severities[" + std::to_string(k) +
                                    "]: " + std::to_string(p.severities[k]) + " is outside " +
                                    range_text(p.kind) + " for " + to_string(p.kind) + " (" +
                                    severity_unit(p.kind) + ")");
      if (k > 0 && !(p.severities[k] > p.severities[k - 1]))
        throw std::invalid_argument(at + "severities[" + std::to_string(k) +
                                    "]: severities must be strictly ascending");
    }
    if (p.seeds.empty()) throw std::invalid_argument(at + "seeds: at least one seed is needed");
    for (size_t k = 0; k < p.seeds.size(); ++k) {
      if (p.kind == PerturbationKind::kPaper && p.seeds[k] > static_cast<uint64_t>(INT_MAX))
        throw std::invalid_argument(at + "seeds[" + std::to_string(k) +
                                    "]: paper's seeds are draw indices, at most 2147483647");
      for (size_t m = 0; m < k; ++m)
        if (p.seeds[m] == p.seeds[k])
          throw std::invalid_argument(at + "seeds[" + std::to_string(k) +
                                      "]: " + std::to_string(p.seeds[k]) + " appears twice");
    }
  }
}

Battery builtin_battery(const std::string& name, int paper_draws) {
  auto seeds = [](int n) {
    std::vector<uint64_t> s;
    for (int i = 0; i < n; ++i) s.push_back(static_cast<uint64_t>(i));
    return s;
  };
  using K = PerturbationKind;
  Battery b;
  b.name = name;
  if (name == "paper") {
    b.perturbations = {{"paper", K::kPaper, {1.0}, seeds(std::max(1, paper_draws))}};
  } else if (name == "default") {
    b.perturbations = {
        {"paper", K::kPaper, {0.25, 0.5, 1.0}, seeds(3)},
        {"voxel-loss", K::kVoxelLoss, {0.02, 0.05, 0.1}, seeds(3)},
        {"limb-loss", K::kLimbLoss, {0.1, 0.2, 0.3}, seeds(3)},
        {"phase-noise", K::kPhaseNoise, {0.1, 0.25, 0.5}, seeds(3)},
        {"amplitude-loss", K::kAmplitudeLoss, {0.25, 0.5, 0.75}, seeds(1)},
        {"friction", K::kFriction, {0.1, 0.5, 2.0}, seeds(1)},
        {"rough-ground", K::kRoughGround, {0.1, 0.25, 0.5}, seeds(3)},
        {"payload", K::kPayload, {0.1, 0.25, 0.5}, seeds(1)},
        {"gravity", K::kGravity, {0.5, 1.5, 2.0}, seeds(1)},
        {"bond-model", K::kBondModel, {1.0}, seeds(1)},
        {"time-step", K::kTimeStep, {0.25, 0.5, 0.75}, seeds(1)},
    };
  } else if (name == "small") {
    b.perturbations = {
        {"paper", K::kPaper, {0.25, 0.5, 1.0}, seeds(1)},
        {"voxel-loss", K::kVoxelLoss, {0.02, 0.05, 0.1}, seeds(1)},
        {"friction", K::kFriction, {0.1, 0.5, 2.0}, seeds(1)},
        {"gravity", K::kGravity, {0.5, 1.5, 2.0}, seeds(1)},
    };
  } else {
    throw std::invalid_argument("unknown built-in battery '" + name +
                                "' (expected default, paper, small or a JSON file)");
  }
  validate(b, name);
  return b;
}

PerturbedLife reference_life(const RobotDef& champion, const PhysicsDef& physics,
                             PerturbationKind kind) {
  if (kind == PerturbationKind::kPaper)
    return {without_development(champion), robustness_physics(physics)};
  return {champion, physics};
}

PerturbedLife perturb(const RobotDef& champion, const PhysicsDef& physics, PerturbationKind kind,
                      double s, uint64_t seed, uint64_t base_seed) {
  if (!in_range(kind, s))
    throw std::invalid_argument(std::string("perturb: severity ") + std::to_string(s) +
                                " is outside " + range_text(kind) + " for " + to_string(kind));
  using K = PerturbationKind;
  if (kind == K::kPaper) {
    if (seed > static_cast<uint64_t>(INT_MAX))
      throw std::invalid_argument("perturb: paper's seed is a draw index, at most 2147483647");
    RobustnessOptions o;
    o.seed = base_seed;
    paper_range(physics, s, &o.e_lo, &o.e_hi);
    return {robustness_draw(champion, physics, o, static_cast<int>(seed)),
            robustness_physics(physics)};
  }
  PerturbedLife life{champion, physics};
  RobotDef& r = life.robot;
  PhysicsDef& p = life.physics;
  Rng rng = Rng::stream(base_seed, StreamPurpose::kBattery, seed, static_cast<uint64_t>(kind));
  switch (kind) {
    case K::kPaper:
      break;
    case K::kVoxelLoss:
      remove_voxels(r, s, rng);
      break;
    case K::kLimbLoss:
      remove_limb(r, s, rng);
      break;
    case K::kPhaseNoise:
      for (int site : present_sites(r)) {
        double ph = r.phase[site] + s * (rng.uniform() - 0.5);
        if (ph >= 1) ph -= 1;  // a whole cycle later: the same wave, back inside (-1, 1)
        if (ph <= -1) ph += 1;
        r.phase[site] = ph;
      }
      break;
    case K::kAmplitudeLoss:
      if (r.act_scale.empty()) r.act_scale.assign(static_cast<size_t>(r.sites()), 1.0);
      for (int site : present_sites(r)) r.act_scale[site] *= 1 - s;
      break;
    case K::kFriction:
      p.mu_static *= s;
      p.mu_kinetic *= s;
      break;
    case K::kRoughGround: {
      if (s == 0) break;  // the flat floor itself
      const double L = r.voxel_size;
      const int margin = 60;  // voxel lengths of ground around the body's birthplace
      GroundDef& g = p.environment.ground;
      g = GroundDef{};
      g.kind = GroundKind::kRough;
      g.cell = L;
      g.origin = {-margin * L, -margin * L};
      g.nx = 2 * margin + r.nx + 1;
      g.ny = 2 * margin + r.ny + 1;
      g.amplitude = s * L;
      g.seed = rng.next_u64();
      break;
    }
    case K::kPayload: {
      if (s == 0) break;
      const std::vector<int> sites = present_sites(r);
      int top = 0;
      for (int site : sites) top = std::max(top, site / (r.nx * r.ny));
      std::vector<int> on_top;
      for (int site : sites)
        if (site / (r.nx * r.ny) == top) on_top.push_back(site);
      const double L = r.voxel_size;
      const double weight =
          static_cast<double>(sites.size()) * p.density * L * L * L * std::abs(p.gravity);
      const double each = s * weight / static_cast<double>(on_top.size());
      for (int site : on_top) r.loads.push_back({site, 0, 0, -each});
      break;
    }
    case K::kGravity:
      p.gravity *= s;
      break;
    case K::kBondModel:
      p.bond_model = p.bond_model == BondModel::kExact ? BondModel::kVoxelyze09 : BondModel::kExact;
      break;
    case K::kTimeStep:
      p.dt_frac *= s;
      break;
  }
  return life;
}

}  // namespace plastivox::analysis
