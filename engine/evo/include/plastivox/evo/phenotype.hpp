// From genome to robot: evaluate the four CPPNs over the lattice, map their outputs to
// voxel properties, keep the geometry rule's voxels, and decide validity.
//
// Output mappings (docs/method.md §6), logistic(o) = 1 / (1 + exp(-o)):
//   geometry     present iff o > 0
//   stiffness    E     = e_min + (e_max - e_min) * logistic(o)      (Pa, linear)
//   development  alpha = -10 + 20 * logistic(o)                     (1/s)
//   phase        phi   = 2 * logistic(o) - 1                        (cycles)
// The robot runs the expression's controller with the genome's controller weights.
// A phenotype is valid when at least min_fill of the lattice sites hold a voxel and no
// output used by it is NaN. Absent sites hold 0 in every array, and dev_rate is 0
// everywhere when the treatment ignores development, so two phenotypes that would simulate
// identically have identical arrays and hash.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "plastivox/base/hash.hpp"
#include "plastivox/evo/genome.hpp"
#include "plastivox/robot.hpp"

namespace plastivox::evo {

enum class GeometryRule {
  kLargestComponent,  // the paper: largest face-connected component of present voxels
  kKeepAll,           // the authors' code: every present voxel
};
const char* to_string(GeometryRule r);                   // "largest-component", "keep-all"
GeometryRule parse_geometry_rule(const std::string& s);  // throws std::invalid_argument

struct ExpressionDef {
  int nx = 10, ny = 10, nz = 10;  // lattice extent, sites
  double voxel_size = 0.01;       // m
  GeometryRule geometry = GeometryRule::kLargestComponent;
  double min_fill = 0.2;             // fraction of sites that must hold a voxel
  double e_min = 1e5, e_max = 1e11;  // Pa, stiffness mapping range (from the physics)
  bool uses_development = true;      // false under treatment none: C3 is ignored
  // The robots' controller (its weights empty: each genome's own go in) and how the genome's
  // controller part is drawn and mutated.
  ControllerDef controller;
  ControllerGenes controller_genes;
};

// Raw CPPN outputs per network and site (NaN where a network produced a non-finite value).
struct NetworkOutputs {
  std::array<std::vector<double>, kNetworkCount> raw;
  std::vector<double> controller;  // the genome's controller weights, passed through as they are
};

struct Phenotype {
  RobotDef robot;  // lattice-sized arrays as described above
  bool valid = false;
  std::string invalid_reason;  // empty when valid
  int voxels = 0;              // voxels kept
  Hash128 hash;  // bit-exact identity of (lattice, present, E0, alpha, phase, controller)
  // Algorithm cma-es: the vector this body expresses (cma_body.hpp), for whoever scores it
  // outside (Python's ask/tell); empty under AFPO. Not part of the identity.
  std::vector<double> vector;
  bool same_as(const Phenotype& o) const;  // bit-exact equality of the arrays
};

double logistic(double o);  // numerically stable; o must not be NaN

// Feeds a robot's identity (lattice, voxel size, present, E0, alpha, phase, and its controller
// when it is not the default sine; bit for bit) to
// `h`: Phenotype::hash, the results file's content digest and the analysis all use it.
void hash_robot(Hasher& h, const RobotDef& r);

// Face-connected (6-neighbour) largest component of present sites. Ties between equally
// large components go to the one holding the lowest site index.
std::vector<uint8_t> largest_component(const std::vector<uint8_t>& present, int nx, int ny, int nz);

// Turns genomes into phenotypes for one lattice. Immutable after construction, so one
// Expresser may be shared by all threads.
class Expresser {
 public:
  explicit Expresser(const ExpressionDef& def);
  const ExpressionDef& def() const { return def_; }
  const CppnInputs& inputs() const { return inputs_; }
  int min_voxels() const { return min_voxels_; }

  NetworkOutputs evaluate(const Genome& g) const;
  void evaluate(const Genome& g, Network n, NetworkOutputs& out) const;  // one network
  Phenotype express(const NetworkOutputs& out) const;
  Phenotype express(const Genome& g) const { return express(evaluate(g)); }

 private:
  ExpressionDef def_;
  CppnInputs inputs_;
  int min_voxels_ = 0;
};

}  // namespace plastivox::evo
