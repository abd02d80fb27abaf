// The evolver's randomness: the base layer's pinned generator (plastivox/base/rng.hpp),
// keyed per decision by (run seed, purpose, generation, individual id).
#pragma once

#include <cstdint>

#include "plastivox/base/rng.hpp"

namespace plastivox::evo {

using plastivox::mix64;
using plastivox::Rng;

// What a stream is for; part of its key so two purposes never share numbers.
enum class StreamPurpose : uint64_t {
  kNewcomer = 1,   // a random individual (initial population or the per-generation newcomer)
  kMutation = 2,   // the mutations that turn a parent into its child
  kCmaSample = 3,  // a CMA-ES sample's normals (cma.hpp), keyed by (generation, id)
  kParent = 4,     // a MAP-Elites child's parent cell (map_elites.hpp), keyed by (generation, id)
  kTest = 99,      // reserved for tests
};

}  // namespace plastivox::evo
