// The engine's elementary functions (engine/core/src/elementary.hpp) on the recording type:
// included, after adj.hpp, by every translation unit of this library that instantiates a kernel
// template on Adj.
#pragma once

#include <numbers>

#include "adj.hpp"
#include "elementary.hpp"

namespace plastivox {
namespace {

// sin(2 pi u) for Adj: the engine's own value (the rounding trick of its range reduction has
// no derivative to record), and its derivative 2 pi cos(2 pi u) = 2 pi sin(2 pi (u + 1/4)).
template <>
inline grad::Adj sin_cycles<grad::Adj>(grad::Adj u) {
  const double s = sin_cycles(u.v);
  return {s, grad::record(u.id, 2.0 * std::numbers::pi * sin_cycles(u.v + 0.25), -1, 0.0)};
}

}  // namespace
}  // namespace plastivox
