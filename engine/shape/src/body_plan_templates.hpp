// Internal: the templates of the body-plan rule (body_plan.hpp) scored against one orientation
// of a body.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "plastivox/analysis/body_plan.hpp"

namespace plastivox::analysis::detail {

// A body's occupancy in its bounding box: U along u (x), V along v (y), Z along z.
struct BodyBox {
  int U = 0, V = 0, Z = 0;
  std::vector<uint8_t> filled;  // U*V*Z, u fastest
  bool at(int u, int v, int z) const { return filled[u + U * (v + V * z)] != 0; }
};

// The box of a voxel set after `quarter_turns` turns of +90 deg about z, moved to the origin.
BodyBox body_box(const VoxelSet& body, int quarter_turns);

// Best template of each plan (Π, Γ, Υ) for this box; PlanMatch::quarter_turns is left 0.
std::array<PlanMatch, 3> match_templates(const BodyBox& box);

}  // namespace plastivox::analysis::detail
