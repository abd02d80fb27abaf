// The templates of the body-plan rule; see body_plan.hpp for the rule itself. Each template
// is a predicate on the cells (u, v, z) of the bounding box, true for template cells.
#include "body_plan_templates.hpp"

#include <algorithm>
#include <string>

namespace plastivox::analysis::detail {

BodyBox body_box(const VoxelSet& body, int quarter_turns) {
  // +90 deg about z: (x, y) -> (-y, x).
  std::vector<Voxel> pts = body.voxels;
  for (int k = 0; k < quarter_turns; ++k)
    for (Voxel& p : pts) p = {-p[1], p[0], p[2]};
  Voxel lo = pts[0], hi = pts[0];
  for (const Voxel& p : pts)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], p[i]);
      hi[i] = std::max(hi[i], p[i]);
    }
  BodyBox box;
  box.U = hi[0] - lo[0] + 1;
  box.V = hi[1] - lo[1] + 1;
  box.Z = hi[2] - lo[2] + 1;
  box.filled.assign(static_cast<size_t>(box.U) * box.V * box.Z, 0);
  for (const Voxel& p : pts)
    box.filled[(p[0] - lo[0]) + box.U * ((p[1] - lo[1]) + box.V * (p[2] - lo[2]))] = 1;
  return box;
}

namespace {

// Scores one template and keeps it in *best if it beats it (strictly: ties keep the first).
// describe() names the template; it is only called for a new best.
template <class InTemplate, class Describe>
void score_template(const BodyBox& box, InTemplate in_template, Describe describe,
                    PlanMatch* best) {
  long t_cells = 0, t_filled = 0, h_cells = 0, h_empty = 0;
  for (int z = 0; z < box.Z; ++z)
    for (int v = 0; v < box.V; ++v)
      for (int u = 0; u < box.U; ++u) {
        const bool f = box.at(u, v, z);
        if (in_template(u, v, z)) {
          ++t_cells;
          t_filled += f;
        } else {
          ++h_cells;
          h_empty += !f;
        }
      }
  const long body = t_filled + (h_cells - h_empty);
  if (t_cells == 0 || h_cells == 0 || body == 0) return;
  const double fill = static_cast<double>(t_filled) / t_cells;
  const double empty = static_cast<double>(h_empty) / h_cells;
  const double inside = static_cast<double>(t_filled) / body;
  const double score = std::min({fill, empty, inside});
  if (score > best->score) {
    best->score = score;
    best->fill = fill;
    best->empty = empty;
    best->inside = inside;
    best->parameters = describe();
  }
}

std::string half(int twice) {  // a half-integer given as twice its value, e.g. 9 -> "4.5"
  return std::to_string(twice / 2) + (twice % 2 ? ".5" : "");
}

}  // namespace

std::array<PlanMatch, 3> match_templates(const BodyBox& box) {
  const int U = box.U, V = box.V, Z = box.Z;
  std::array<PlanMatch, 3> best;
  best[0].plan = BodyPlan::kPi;
  best[1].plan = BodyPlan::kGamma;
  best[2].plan = BodyPlan::kUpsilon;

  // Π: two full-width legs at both ends of u, a bridge on top; gap >= 2 wide and >= 2 high.
  for (int a1 = 1; a1 <= U - 3; ++a1)
    for (int a2 = 1; a1 + a2 <= U - 2; ++a2)
      for (int b = 1; b <= Z - 2; ++b)
        score_template(
            box, [&](int u, int, int z) { return u < a1 || u >= U - a2 || z >= Z - b; },
            [&] {
              return "legs " + std::to_string(a1) + "+" + std::to_string(a2) + ", bridge " +
                     std::to_string(b);
            },
            &best[0]);

  // Γ: a wall at the start of u meeting a second plate at one of its ends.
  for (int a = 1; a <= U - 2; ++a) {
    for (int b = 1; b <= Z - 2; ++b) {
      score_template(
          box, [&](int u, int, int z) { return u < a || z < b; },
          [&] {
            return "side L: wall " + std::to_string(a) + ", floor plate " + std::to_string(b);
          },
          &best[1]);
      score_template(
          box, [&](int u, int, int z) { return u < a || z >= Z - b; },
          [&] { return "side Γ: wall " + std::to_string(a) + ", top bar " + std::to_string(b); },
          &best[1]);
    }
    for (int b = 1; b <= V - 2; ++b)
      score_template(
          box, [&](int u, int v, int) { return u < a || v < b; },
          [&] { return "plan L: walls " + std::to_string(a) + " and " + std::to_string(b); },
          &best[1]);
  }

  // Υ: a thin full wall at the start of u and a round rod from it to the far end, centred in
  // the middle half of the wall. Coordinates doubled so centres and radii may be half cells.
  const int max_wall = std::max(1, U / 3);
  const int max_h = 2 * std::min(V, Z) / 3;  // twice the largest radius
  for (int a = 1; a <= max_wall && U - a >= 2; ++a)
    for (int h = 2; h <= max_h; ++h)
      for (int cz = (Z + 1) / 2; cz <= 3 * Z / 2; ++cz)
        for (int cv = (V + 1) / 2; cv <= 3 * V / 2; ++cv)
          score_template(
              box,
              [&](int u, int v, int z) {
                if (u < a) return true;
                const int dv = 2 * v + 1 - cv, dz = 2 * z + 1 - cz;
                return dv * dv + dz * dz <= h * h;
              },
              [&] {
                return "wall " + std::to_string(a) + ", rod radius " + half(h) + " at v " +
                       half(cv) + ", z " + half(cz);
              },
              &best[2]);
  return best;
}

}  // namespace plastivox::analysis::detail
