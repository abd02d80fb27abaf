// A CMA-ES genome on its fixed body: dimension, start, and the body with a vector applied.
#include "plastivox/evo/cma_body.hpp"

#include <algorithm>
#include <cmath>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/robot_file.hpp"

namespace plastivox::evo {
namespace {

std::vector<int> voxel_sites(const RobotDef& r) {
  std::vector<int> sites;
  for (int i = 0; i < r.sites(); ++i)
    if (r.present[i]) sites.push_back(i);
  return sites;
}

bool searches_development(const EvolveConfig& c) {
  return c.treatment != Treatment::kNone;
}

// logistic^-1((v - lo) / (hi - lo)), clamped to [-30, 30] (the ends map to the clamp).
double logit_in(double v, double lo, double hi) {
  const double u = (v - lo) / (hi - lo);
  if (!(u > 0)) return -30;
  if (!(u < 1)) return 30;
  return std::clamp(std::log(u / (1 - u)), -30.0, 30.0);
}

// A phase in cycles into (-1, 1), whole cycles off: values already inside are kept as they
// are (so the body's own phases start the search exactly), +-1 is 0.
double wrap_phase(double x) {
  const double w = x - 2 * std::round(x / 2);
  return std::abs(w) < 1 ? w : 0.0;
}

}  // namespace

double default_sigma(GenomeKind g) {
  return g == GenomeKind::kController ? 0.5 : g == GenomeKind::kPhase ? 0.25 : 1.0;
}

int genome_dimension(const EvolveConfig& c) {
  const RobotDef& b = c.cma.body;
  switch (c.cma.genome) {
    case GenomeKind::kController:
      return weight_count(b.controller.kind, b.controller.hidden);
    case GenomeKind::kPhase:
      return b.voxel_count();
    case GenomeKind::kMaterials:
      return b.voxel_count() * (searches_development(c) ? 2 : 1);
  }
  return 0;
}

std::vector<double> genome_start(const EvolveConfig& c) {
  const RobotDef& b = c.cma.body;
  const std::vector<int> sites = voxel_sites(b);
  std::vector<double> x;
  switch (c.cma.genome) {
    case GenomeKind::kController:
      x = b.controller.weights;
      x.resize(genome_dimension(c), 0.0);  // a body without weights starts from zero
      break;
    case GenomeKind::kPhase:
      for (int s : sites) x.push_back(b.phase[s]);
      break;
    case GenomeKind::kMaterials:
      for (int s : sites)
        x.push_back(logit_in(std::log(b.stiffness[s]), std::log(c.physics.e_min),
                             std::log(c.physics.e_max)));
      if (searches_development(c))
        for (int s : sites) x.push_back(logit_in(b.dev_rate[s], -10, 10));
      break;
  }
  return x;
}

Phenotype express_vector(const EvolveConfig& c, const std::vector<double>& x) {
  Phenotype p;
  p.robot = c.cma.body;
  RobotDef& r = p.robot;
  for (double v : x)
    if (!std::isfinite(v)) {
      p.invalid_reason = "the genome holds a non-finite number";
      return p;
    }
  const std::vector<int> sites = voxel_sites(r);
  const size_t n = sites.size();
  switch (c.cma.genome) {
    case GenomeKind::kController:
      r.controller.weights = x;
      break;
    case GenomeKind::kPhase:
      for (size_t k = 0; k < n; ++k) r.phase[sites[k]] = wrap_phase(x[k]);
      break;
    case GenomeKind::kMaterials:
      for (size_t k = 0; k < n; ++k)
        r.stiffness[sites[k]] =
            std::exp(std::log(c.physics.e_min) +
                     (std::log(c.physics.e_max) - std::log(c.physics.e_min)) * logistic(x[k]));
      if (searches_development(c))
        for (size_t k = 0; k < n; ++k) r.dev_rate[sites[k]] = -10 + 20 * logistic(x[n + k]);
      break;
  }
  p.valid = true;
  p.voxels = static_cast<int>(n);
  p.vector = x;
  Hasher h;
  hash_robot(h, r);
  p.hash = h.finish();
  return p;
}

RobotDef read_body(const std::string& path, const std::string& source) {
  const std::string where = source + ": body: ";
  const bool results = path.size() > 3 && path.compare(path.size() - 3, 3, ".h5") == 0;
  try {
    if (!results) return read_robot_file(path).robot;
    const ResultsFile f = read_results(path);
    return champion_robot(champion_at(f.state, -1, path), f.state.generations_done);
  } catch (const std::exception& e) {
    throw InputError(where + e.what());
  }
}

}  // namespace plastivox::evo
