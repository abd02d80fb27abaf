// The evolver's parallel loop is the base layer's (plastivox/base/parallel.hpp).
#pragma once

#include "plastivox/base/parallel.hpp"

namespace plastivox::evo {
using plastivox::hardware_threads;
using plastivox::parallel_for;
}  // namespace plastivox::evo
