// The evolver's hashes are the base layer's (plastivox/base/hash.hpp).
#pragma once

#include "plastivox/base/hash.hpp"

namespace plastivox::evo {
using plastivox::Hash128;
using plastivox::Hasher;
}  // namespace plastivox::evo
