#include "plastivox/evo/genome.hpp"

#include <stdexcept>
#include <string>

namespace plastivox::evo {

const char* to_string(Network n) {
  switch (n) {
    case Network::kGeometry:
      return "geometry";
    case Network::kStiffness:
      return "stiffness";
    case Network::kDevelopment:
      return "development";
    case Network::kPhase:
      return "phase";
  }
  return "?";
}

Genome random_genome(Rng& rng) {
  Genome g;
  for (Cppn& net : g.nets) net = random_cppn(rng);
  return g;
}

void validate(const Genome& g) {
  for (int i = 0; i < kNetworkCount; ++i) {
    try {
      validate(g.nets[i]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(to_string(static_cast<Network>(i))) +
                                  " network: " + e.what());
    }
  }
}

}  // namespace plastivox::evo
