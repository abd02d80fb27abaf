// Genome -> phenotype: output mappings, geometry rule, validity, identity hash.
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/io/limits.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "plastivox/base/names.hpp"

namespace plastivox::evo {

namespace {
constexpr Named<GeometryRule> kGeometryRuleNames[] = {
    {GeometryRule::kLargestComponent, "largest-component"}, {GeometryRule::kKeepAll, "keep-all"}};
}  // namespace

const char* to_string(GeometryRule r) {
  return name_in(kGeometryRuleNames, r);
}

GeometryRule parse_geometry_rule(const std::string& s) {
  if (const auto r = value_in(kGeometryRuleNames, s)) return *r;
  throw std::invalid_argument("geometry rule '" + s + "' is unknown (use " +
                              choices_in(kGeometryRuleNames) + ")");
}

void hash_robot(Hasher& h, const RobotDef& r) {
  h.u64(static_cast<uint64_t>(r.nx));
  h.u64(static_cast<uint64_t>(r.ny));
  h.u64(static_cast<uint64_t>(r.nz));
  h.f64(r.voxel_size);
  h.vec(r.present);
  h.vec(r.stiffness);
  h.vec(r.dev_rate);
  h.vec(r.phase);
  if (!r.controller.is_default()) {  // only then, so the sine's hashes and digests hold
    h.str(to_string(r.controller.kind));
    h.u64(static_cast<uint64_t>(r.controller.hidden));
    h.u64(static_cast<uint64_t>(r.controller.every));
    h.vec(r.controller.weights);
  }
}

double logistic(double o) {
  // Never exponentiate a large positive number: exp(-|o|) is in (0, 1].
  if (o >= 0) return 1.0 / (1.0 + std::exp(-o));
  const double e = std::exp(o);
  return e / (1.0 + e);
}

std::vector<uint8_t> largest_component(const std::vector<uint8_t>& present, int nx, int ny,
                                       int nz) {
  const int n = nx * ny * nz;
  std::vector<int> label(n, -1);
  std::vector<int> stack;
  int best_label = -1, best_size = 0, next_label = 0;
  for (int start = 0; start < n; ++start) {
    if (!present[start] || label[start] >= 0) continue;
    // Depth-first flood fill of one component; components are found in increasing order
    // of their lowest site, so keeping the first of equal size is the documented tie rule.
    const int id = next_label++;
    int size = 0;
    label[start] = id;
    stack.push_back(start);
    while (!stack.empty()) {
      const int s = stack.back();
      stack.pop_back();
      ++size;
      const int x = s % nx, y = (s / nx) % ny, z = s / (nx * ny);
      const int neighbours[6][2] = {{x > 0, s - 1},       {x + 1 < nx, s + 1},
                                    {y > 0, s - nx},      {y + 1 < ny, s + nx},
                                    {z > 0, s - nx * ny}, {z + 1 < nz, s + nx * ny}};
      for (const auto& nb : neighbours) {
        if (!nb[0] || !present[nb[1]] || label[nb[1]] >= 0) continue;
        label[nb[1]] = id;
        stack.push_back(nb[1]);
      }
    }
    if (size > best_size) {
      best_size = size;
      best_label = id;
    }
  }
  std::vector<uint8_t> keep(n, 0);
  for (int s = 0; s < n; ++s) keep[s] = label[s] == best_label && best_label >= 0 ? 1 : 0;
  return keep;
}

bool Phenotype::same_as(const Phenotype& o) const {
  auto same = [](const auto& a, const auto& b) {
    // (memcmp of two empty vectors would pass null pointers: undefined, even for 0 bytes)
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
  };
  return robot.nx == o.robot.nx && robot.ny == o.robot.ny && robot.nz == o.robot.nz &&
         same(robot.present, o.robot.present) && same(robot.stiffness, o.robot.stiffness) &&
         same(robot.dev_rate, o.robot.dev_rate) && same(robot.phase, o.robot.phase) &&
         robot.controller.kind == o.robot.controller.kind &&
         robot.controller.hidden == o.robot.controller.hidden &&
         robot.controller.every == o.robot.controller.every &&
         same(robot.controller.weights, o.robot.controller.weights);
}

Expresser::Expresser(const ExpressionDef& def)
    : def_(def), inputs_(lattice_inputs(def.nx, def.ny, def.nz)) {
  // The smallest voxel count that is at least min_fill of the sites (tolerant of the
  // rounding in e.g. 0.2 * 1000).
  min_voxels_ = static_cast<int>(std::ceil(def.min_fill * inputs_.sites - 1e-9));
}

void Expresser::evaluate(const Genome& g, Network n, NetworkOutputs& out) const {
  std::vector<double> scratch;
  evo::evaluate(g.net(n), inputs_, out.raw[static_cast<int>(n)], scratch);
}

NetworkOutputs Expresser::evaluate(const Genome& g) const {
  NetworkOutputs out;
  std::vector<double> scratch;
  for (int i = 0; i < kNetworkCount; ++i) evo::evaluate(g.nets[i], inputs_, out.raw[i], scratch);
  out.controller = g.controller;
  return out;
}

Phenotype Expresser::express(const NetworkOutputs& out) const {
  Phenotype p;
  RobotDef& r = p.robot;
  r = make_empty_robot(def_.nx, def_.ny, def_.nz, def_.voxel_size, limits_from_environment());
  const int n = r.sites();
  auto invalid = [&p](const std::string& why) {
    if (p.valid) {
      p.valid = false;
      p.invalid_reason = why;
    }
  };
  p.valid = true;

  // Geometry. A NaN output cannot say present or absent: the phenotype is invalid.
  const std::vector<double>& geo = out.raw[static_cast<int>(Network::kGeometry)];
  for (int s = 0; s < n; ++s) {
    if (std::isnan(geo[s])) {
      invalid("geometry network output is NaN");
      continue;
    }
    r.present[s] = geo[s] > 0 ? 1 : 0;
  }
  if (def_.geometry == GeometryRule::kLargestComponent)
    r.present = largest_component(r.present, r.nx, r.ny, r.nz);
  p.voxels = r.voxel_count();
  if (p.voxels < min_voxels_)
    invalid(std::to_string(p.voxels) + " voxels, fewer than " + std::to_string(min_voxels_) +
            " (min_fill)");

  // Per-voxel properties where a voxel is present; 0 elsewhere.
  const std::vector<double>& stiff = out.raw[static_cast<int>(Network::kStiffness)];
  const std::vector<double>& devo = out.raw[static_cast<int>(Network::kDevelopment)];
  const std::vector<double>& phase = out.raw[static_cast<int>(Network::kPhase)];
  for (int s = 0; s < n; ++s) {
    if (!r.present[s]) continue;
    if (std::isnan(stiff[s]))
      invalid("stiffness network output is NaN");
    else
      r.stiffness[s] = def_.e_min + (def_.e_max - def_.e_min) * logistic(stiff[s]);
    if (def_.uses_development) {
      if (std::isnan(devo[s]))
        invalid("development network output is NaN");
      else
        r.dev_rate[s] = -10.0 + 20.0 * logistic(devo[s]);
    }
    if (std::isnan(phase[s]))
      invalid("phase network output is NaN");
    else
      r.phase[s] = 2.0 * logistic(phase[s]) - 1.0;
  }

  r.controller = def_.controller;
  r.controller.weights = out.controller;
  if (out.controller.size() != static_cast<size_t>(def_.controller_genes.count))
    invalid("the genome has " + std::to_string(out.controller.size()) +
            " controller weights, the controller takes " +
            std::to_string(def_.controller_genes.count));

  Hasher h;
  hash_robot(h, r);
  p.hash = h.finish();
  return p;
}

}  // namespace plastivox::evo
