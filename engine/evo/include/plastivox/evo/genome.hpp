// A robot's genome: four independent CPPNs (docs/method.md §6).
#pragma once

#include <array>

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

struct Genome {
  std::array<Cppn, kNetworkCount> nets;
  const Cppn& net(Network n) const { return nets[static_cast<int>(n)]; }
  bool operator==(const Genome&) const = default;
};

// Four networks from random_cppn(), drawn in network order from one stream.
Genome random_genome(Rng& rng);

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
