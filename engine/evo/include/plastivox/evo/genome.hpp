// A robot's genome: four independent CPPNs (docs/method.md §6), and the weights of its
// controller when the run evolves one (docs/evolution.md, "Evolving a controller").
#pragma once

#include <array>
#include <vector>

#include "plastivox/evo/cppn.hpp"
#include "plastivox/evo/rng.hpp"

namespace plastivox::evo {

// Which robot property a network encodes; also its index in Genome::nets.
enum class Network : int {
  kGeometry = 0,     // C1: a voxel is present where the output is > 0
  kStiffness = 1,    // C2: congenital Young's modulus
  kDevelopment = 2,  // C3: development rate alpha
  kPhase = 3,        // C4: actuation phase
};
constexpr int kNetworkCount = 4;
const char* to_string(Network n);  // "geometry", "stiffness", "development", "phase"

// The controller part of a genome: `count` weights (weight_count of the run's controller; 0
// under the sine, whose genomes have none). A newcomer draws each from N(0, init_sigma^2); a
// mutation adds N(0, sigma^2) to each weight with probability `rate` (to one weight, chosen
// uniformly, when the draw picked none).
struct ControllerGenes {
  int count = 0;
  double init_sigma = 1.0;
  double rate = 0.1;
  double sigma = 0.3;
  bool operator==(const ControllerGenes&) const = default;
};

struct Genome {
  std::array<Cppn, kNetworkCount> nets;
  std::vector<double> controller;  // the controller's weights (ControllerGenes::count)
  const Cppn& net(Network n) const { return nets[static_cast<int>(n)]; }
  bool operator==(const Genome&) const = default;
};

// Four networks from random_cppn(), drawn in network order from one stream, then the
// controller's weights (none when genes.count is 0, which draws nothing more).
Genome random_genome(Rng& rng, const ControllerGenes& genes = {});

// The controller part's mutation (ControllerGenes): always changes at least one weight.
void mutate_controller(std::vector<double>& weights, const ControllerGenes& genes, Rng& rng);

void validate(const Genome& g);  // std::invalid_argument naming the network

// The paper's three body plans as hand-built geometry networks, for a run's optional seeded
// start (config `initial_population: body-plans`, docs/evolution.md): 0 Π (legs at both ends
// of x under a bridge), 1 Γ (a wall at one end of x on a floor plate), 2 Υ (an upright plate at
// one end of x with a round rod along x from its centre). Each output is max(a, b) of two
// half-space or cylinder terms, written (a + b + |a - b|) / 2 with abs and square nodes, so
// the shape follows the rescaled inputs and holds on any lattice of 6 sites a side or more
// (on 5 the Π's gap is one site wide). Ordinary networks: mutation changes them like any other.
constexpr int kBodyPlanSeedCount = 3;
Cppn body_plan_geometry(int plan);  // plan in [0, kBodyPlanSeedCount)

}  // namespace plastivox::evo
