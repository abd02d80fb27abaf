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

}  // namespace plastivox::evo
