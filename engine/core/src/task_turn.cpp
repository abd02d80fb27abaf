// turn: the body's net rotation about the vertical axis from the end of settling to the end
// of the life, in radians, |theta(T)|, either way round.
//
// A soft body has no one orientation: each voxel turns on its own as the body flexes, and a
// principal axis of the footprint is undefined for a square one. The turn used here is the
// rotation about z that best carries the body's settled horizontal layout onto its present
// one. With r0_i the horizontal offset of voxel i's centre from the centre of mass when
// settling ended, and r_i its offset now, the least-squares angle (2-D Procrustes) is
//   theta = atan2(sum_i r0_i x r_i, sum_i r0_i . r_i).
// It is exact for a rigid turn, ignores where the body walked (offsets from the centre of
// mass) and its tilt (x and y only), and weighs every voxel alike. atan2 wraps at ±pi, so
// the watch follows (dot, cross) every step and counts whole turns as it crosses the
// negative dot axis (a step turns a body far less than half a turn). A body whose voxel
// centres all lie on one vertical line has no layout to turn, and scores 0.
#include <cmath>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kTwoPi = 6.283185307179586476925287;

// task_values: 1 once the settled layout is taken (task_layout, per voxel: its horizontal
// offset from the centre of mass), the sums at the last state seen (m^2), and the whole turns
// counted (+ anticlockwise seen from above).
constexpr int kTurnLaid = 0, kTurnDot = 1, kTurnCross = 2, kTurnTurns = 3;

}  // namespace

void see_turn(const Model& m, State& s) {
  if (!s.settled) return;
  TaskValues& v = s.task_values;
  if (v[kTurnLaid] == 0) {  // the first state after settling: the layout turns are measured from
    for (int i = 0; i < m.robot_n; ++i)
      s.task_layout[i] = {s.pos[i].x() - s.com_settled.x(), s.pos[i].y() - s.com_settled.y()};
    v[kTurnLaid] = 1;
  }
  const Vec3 c = body_center_of_mass(m, s);
  double dot = 0, cross = 0;
  for (int i = 0; i < m.robot_n; ++i) {
    const double x = s.pos[i].x() - c.x(), y = s.pos[i].y() - c.y();
    const double x0 = s.task_layout[i].x(), y0 = s.task_layout[i].y();
    dot += x0 * x + y0 * y;
    cross += x0 * y - y0 * x;
  }
  // Through +pi (cross from >= 0 to < 0 behind the axis) is a whole turn more; back, one less.
  if (dot < 0 && (cross < 0) != (v[kTurnCross] < 0)) v[kTurnTurns] += cross < 0 ? 1 : -1;
  v[kTurnDot] = dot;
  v[kTurnCross] = cross;
}

double turn_score(const Model&, const State& s, const SimResult&) {
  const TaskValues& v = s.task_values;
  if (v[kTurnLaid] == 0) return 0;  // never settled
  // cross == 0 behind the axis is +pi, as the count above takes it (not -pi for -0.0).
  const double theta =
      std::atan2(v[kTurnCross] == 0 ? 0.0 : v[kTurnCross], v[kTurnDot]) + kTwoPi * v[kTurnTurns];
  return std::abs(theta);
}

std::vector<const char*> turn_values() {
  return {"1 once the settled layout (task_layout) is taken",
          "sum of the layout's dot products with the present offsets, m^2",
          "sum of their cross products, m^2", "whole turns counted, + anticlockwise"};
}

}  // namespace plastivox
