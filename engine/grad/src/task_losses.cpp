// Every task's fitness as a loss of the life's states (gradient.hpp, task_loss).
//
// Each loss computes its value as the task's score does (engine/core/src/task_*.cpp; the
// formulas are docs/tasks.md's), in the same order of operations, so the value is simulate()'s
// fitness bit for bit (grad_task_test). It reads the physics rows alone (positions,
// com_settled), never the watches (task_values, task_layout), which the replica of the backward
// pass does not keep: the tasks whose score needs more than the last state (jump, turn, carry,
// push) follow the states themselves as their watch does, and remember the steps whose states
// the fitness is a function of. The derivative is the pathwise one of docs/gradients.md ("Where
// a stage has no derivative"): at a maximum, a minimum or a clamp, that of the branch the life
// took.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"
#include "plastivox/task.hpp"
#include "tasks.hpp"

namespace plastivox::grad {
namespace {

using Rows = std::vector<std::vector<double>>;

size_t row(const char* name) {
  return static_cast<size_t>(&state_field(name) - kStateFields.data());
}

// Adds g (per m of the mean, x, y, z) to the derivative of each voxel centre of [begin, end)
// whose mean it is (body_center_of_mass, object_center: the sum over the count).
void add_to_mean(Rows& d, int begin, int end, const double g[3]) {
  std::vector<double>& pos = d[row("pos")];
  const double count = end - begin;
  for (int i = begin; i < end; ++i)
    for (int k = 0; k < 3; ++k) pos[3 * size_t(i) + k] += g[k] / count;
}

void add_to_com_settled(Rows& d, const double g[3]) {
  for (int k = 0; k < 3; ++k) d[row("com_settled")][k] += g[k];
}

// FNV-1a of a few numbers: a loss's branches (TrajectoryLoss::branches).
uint64_t signature(std::initializer_list<double> values) {
  uint64_t h = 1469598103934665603ull;
  for (double v : values) {
    const auto bits = static_cast<uint64_t>(static_cast<int64_t>(v));
    for (int k = 0; k < 8; ++k) h = (h ^ ((bits >> (8 * k)) & 0xff)) * 1099511628211ull;
  }
  return h;
}

// ---- walk, rough, obstacles, climb, slope: functions of the last state alone ----

// The centres of mass the score reads (fill_displacement): now, and at settling (now before).
struct Centres {
  Vec3 com, settled;
};
Centres centres(const Model& m, const State& s) {
  const Vec3 com = body_center_of_mass(m, s);
  return {com, s.settled ? s.com_settled : com};
}

// One score of the last state: its value, and its derivative with respect to the centre of
// mass now (d_com) and at settling (d_settled), each per m.
struct FinalScore {
  double value = 0;
  double d_com[3] = {0, 0, 0}, d_settled[3] = {0, 0, 0};
};

// walk: |d|, d = (c - c_settled) / L, z dropped under xy fitness. |d| has no derivative at 0:
// 0 there.
FinalScore walk_score_of(const Model& m, const Centres& c) {
  FinalScore out;
  const Vec3 d = displacement_since_settling(m, c.settled, c.com);
  out.value = d.norm();
  if (!(out.value > 0)) return out;
  for (int k = 0; k < 3; ++k) {
    out.d_com[k] = d[k] / out.value / m.size;
    out.d_settled[k] = -out.d_com[k];
  }
  return out;
}

// The horizontal displacement |c_xy - c_settled_xy| (m; horizontal_displacement) and its
// derivative with respect to c_xy (the negative with respect to c_settled_xy); 0 at 0.
double horizontal(const Centres& c, double g[2]) {
  const double value = (c.com - c.settled).head<2>().norm();
  g[0] = g[1] = 0;
  if (value > 0)
    for (int k = 0; k < 2; ++k) g[k] = (c.com[k] - c.settled[k]) / value;
  return value;
}

// The rise of the ground under the centre of mass (ground_rise, m) and its slopes under each
// centre: the height field is bilinear between nodes, so its slope is that of the cell the
// point lies in (at a node line, the cell on its + side, as HeightField::height locates it;
// 0 past the grid and on level ground).
double rise(const Model& m, const Centres& c, double g_com[2], double g_settled[2]) {
  g_com[0] = g_com[1] = g_settled[0] = g_settled[1] = 0;
  if (!m.terrain) return 0;
  const double h = m.ground.height(c.com.x(), c.com.y(), &g_com[0], &g_com[1]);
  return h - m.ground.height(c.settled.x(), c.settled.y(), &g_settled[0], &g_settled[1]);
}

// rough, obstacles: |c_xy(T) - c_xy(settle)| / L (horizontal_travel).
FinalScore horizontal_score_of(const Model& m, const Centres& c) {
  FinalScore out;
  double g[2];
  out.value = horizontal(c, g) / m.size;
  for (int k = 0; k < 2; ++k) out.d_com[k] = g[k] / m.size, out.d_settled[k] = -out.d_com[k];
  return out;
}

// climb: max(0, |c_xy(T) - c_xy(settle)| + w (h(c(T)) - h(c(settle)))) / L. At or below 0 the
// clamp holds: derivative 0.
FinalScore climb_score_of(const Model& m, const Centres& c) {
  FinalScore out;
  const double w = task_param(m.def, "height_weight");
  double g[2], gh[2], gh0[2];
  const double travel = horizontal(c, g), up = rise(m, c, gh, gh0);
  out.value = std::max(0.0, travel + w * up) / m.size;
  if (!(travel + w * up > 0)) return out;
  for (int k = 0; k < 2; ++k) {
    out.d_com[k] = (g[k] + w * gh[k]) / m.size;
    out.d_settled[k] = (-g[k] - w * gh0[k]) / m.size;
  }
  return out;
}

// slope: max(0, h(c(T)) - h(c(settle))) / L; derivative 0 where the clamp holds.
FinalScore slope_score_of(const Model& m, const Centres& c) {
  FinalScore out;
  double gh[2], gh0[2];
  const double up = rise(m, c, gh, gh0);
  out.value = std::max(0.0, up) / m.size;
  if (!(up > 0)) return out;
  for (int k = 0; k < 2; ++k) out.d_com[k] = gh[k] / m.size, out.d_settled[k] = -gh0[k] / m.size;
  return out;
}

TrajectoryLoss final_loss(const Model& m, FinalScore (*score)(const Model&, const Centres&)) {
  auto last = std::make_shared<int64_t>(-1);
  TrajectoryLoss loss;
  loss.see = [](const State&) {};
  loss.value = [&m, score, last](const State& s) {
    *last = s.steps;
    return score(m, centres(m, s)).value;
  };
  loss.adjoint = [&m, score, last](const State& s, Rows& d) {
    if (s.steps != *last) return false;
    const FinalScore f = score(m, centres(m, s));
    if (!s.settled) return true;  // c_settled is c itself: the score is 0 whatever c is
    add_to_mean(d, 0, m.robot_n, f.d_com);
    add_to_com_settled(d, f.d_settled);
    return true;
  };
  loss.branches = [&m, score, last] { return signature({double(*last)}); };
  return loss;
}

// ---- jump: max over the states after settling of (c_z(t) - c_z(settle)) / L ----
// The derivative is that of the first state attaining the maximum (see_jump keeps the first:
// std::max keeps the running value at a tie); the maximum starts at 0, which the settled
// state attains exactly (its centre is com_settled).
TrajectoryLoss jump_loss(const Model& m) {
  struct Jump {
    double highest = 0;
    int64_t at = -1;  // the step of the state that set it; -1: none above 0
  };
  auto j = std::make_shared<Jump>();
  TrajectoryLoss loss;
  loss.see = [&m, j](const State& s) {
    if (!s.settled) return;
    const double up = body_center_of_mass(m, s).z() - s.com_settled.z();
    if (j->highest < up) j->highest = up, j->at = s.steps;
  };
  loss.value = [&m, j](const State&) { return j->highest / m.size; };
  loss.adjoint = [&m, j](const State& s, Rows& d) {
    if (s.steps != j->at) return false;
    const double g[3] = {0, 0, 1 / m.size}, g_settled[3] = {0, 0, -1 / m.size};
    add_to_mean(d, 0, m.robot_n, g);
    add_to_com_settled(d, g_settled);
    return true;
  };
  loss.branches = [j] { return signature({double(j->at)}); };
  return loss;
}

// ---- turn: |theta(T)|, theta = atan2(C, D) + 2 pi turns ----
// D = sum_i r0_i . r_i, C = sum_i r0_i x r_i: r0_i voxel i's horizontal offset from
// com_settled in the first state after settling (the layout), r_i its offset from the centre
// of mass in the last. The count of whole turns is discrete (derivative 0); |theta| at 0 has
// no derivative: 0 there.
TrajectoryLoss turn_loss(const Model& m) {
  struct Turn {
    bool laid = false;
    int64_t laid_at = -1, last = -1;
    std::vector<double> x0, y0, x, y;  // the layout, and the offsets of the last state seen
    double dot = 0, cross = 0, turns = 0;
    double g_dot = 0, g_cross = 0;  // d |theta| / dD, dC (set with the value)
  };
  auto t = std::make_shared<Turn>();
  TrajectoryLoss loss;
  loss.see = [&m, t](const State& s) {  // see_turn, step for step
    if (!s.settled) return;
    const int n = m.robot_n;
    if (!t->laid) {
      t->x0.resize(n), t->y0.resize(n), t->x.resize(n), t->y.resize(n);
      for (int i = 0; i < n; ++i)
        t->x0[i] = s.pos[i].x() - s.com_settled.x(), t->y0[i] = s.pos[i].y() - s.com_settled.y();
      t->laid = true;
      t->laid_at = s.steps;
    }
    const Vec3 c = body_center_of_mass(m, s);
    double dot = 0, cross = 0;
    for (int i = 0; i < n; ++i) {
      const double x = s.pos[i].x() - c.x(), y = s.pos[i].y() - c.y();
      const double x0 = t->x0[i], y0 = t->y0[i];
      dot += x0 * x + y0 * y;
      cross += x0 * y - y0 * x;
      t->x[i] = x, t->y[i] = y;
    }
    if (dot < 0 && (cross < 0) != (t->cross < 0)) t->turns += cross < 0 ? 1 : -1;
    t->dot = dot;
    t->cross = cross;
    t->last = s.steps;
  };
  loss.value = [t](const State&) {
    if (!t->laid) return 0.0;
    constexpr double kTwoPi = 6.283185307179586476925287;
    const double theta = std::atan2(t->cross == 0 ? 0.0 : t->cross, t->dot) + kTwoPi * t->turns;
    const double r2 = t->dot * t->dot + t->cross * t->cross;
    const double sign = theta > 0 ? 1 : theta < 0 ? -1 : 0;
    if (r2 > 0) t->g_dot = -sign * t->cross / r2, t->g_cross = sign * t->dot / r2;
    return std::abs(theta);
  };
  loss.adjoint = [&m, t](const State& s, Rows& d) {
    if (!t->laid || (s.steps != t->last && s.steps != t->laid_at)) return false;
    const int n = m.robot_n;
    std::vector<double>& pos = d[row("pos")];
    const double gd = t->g_dot, gc = t->g_cross;
    if (s.steps == t->last) {  // through r_i = p_i - c, c the mean of the p_i
      double mean[2] = {0, 0};
      for (int i = 0; i < n; ++i) {
        mean[0] += gd * t->x0[i] - gc * t->y0[i];
        mean[1] += gd * t->y0[i] + gc * t->x0[i];
      }
      for (int i = 0; i < n; ++i) {
        pos[3 * size_t(i)] += gd * t->x0[i] - gc * t->y0[i] - mean[0] / n;
        pos[3 * size_t(i) + 1] += gd * t->y0[i] + gc * t->x0[i] - mean[1] / n;
      }
    }
    if (s.steps == t->laid_at) {  // through r0_i = p_i - com_settled
      double g_settled[3] = {0, 0, 0};
      for (int i = 0; i < n; ++i) {
        const double gx = gd * t->x[i] + gc * t->y[i], gy = gd * t->y[i] - gc * t->x[i];
        pos[3 * size_t(i)] += gx;
        pos[3 * size_t(i) + 1] += gy;
        g_settled[0] -= gx, g_settled[1] -= gy;
      }
      add_to_com_settled(d, g_settled);
    }
    return true;
  };
  loss.branches = [t] { return signature({t->turns, double(t->laid_at), double(t->last)}); };
  return loss;
}

// ---- carry and push: horizontal travels between two states ----

// A point's horizontal travel from its first place to its last (travel_to), the steps of the
// two states and the voxels whose mean the point is.
struct Travel {
  double first[2] = {0, 0}, last[2] = {0, 0};
  int64_t from = -1, to = -1;
  int begin = 0, end = 0;
  void go(const Vec3& p, int64_t step, bool start) {
    last[0] = p.x(), last[1] = p.y(), to = step;
    if (start) first[0] = last[0], first[1] = last[1], from = step;
  }
  double value(const Model& m) const {  // travel_voxel_lengths
    return std::hypot(last[0] - first[0], last[1] - first[1]) / m.size;
  }
  // d value / d state at `step`: + along the travel at its last state, - at its first (0 when
  // it did not move: |.| at 0).
  bool adjoint(const Model& m, const State& s, Rows& d) const {
    if (from < 0 || (s.steps != from && s.steps != to) || from == to) return false;
    const double dx = last[0] - first[0], dy = last[1] - first[1], len = std::hypot(dx, dy);
    if (!(len > 0)) return false;
    const double sign = s.steps == to ? 1 : -1;
    const double g[3] = {sign * dx / len / m.size, sign * dy / len / m.size, 0};
    add_to_mean(d, begin, end, g);
    return true;
  }
};

// carry: min(payload's travel, body's travel) while the payload is off the ground (see_carry).
// The derivative is the lesser's (the payload's at a tie, as std::min keeps its first).
TrajectoryLoss carry_loss(const Model& m) {
  struct Carry {
    bool dropped = false, started = false;
    Travel payload, body;
    bool body_lesser = false;
  };
  auto c = std::make_shared<Carry>();
  c->body.end = m.robot_n;
  if (m.object_count() > 0)
    c->payload.begin = m.object_begin[0], c->payload.end = m.object_begin[1];
  TrajectoryLoss loss;
  loss.see = [&m, c](const State& s) {
    if (!s.settled || c->dropped || m.object_count() == 0) return;
    for (int i = c->payload.begin; i < c->payload.end; ++i) {  // off_ground
      const Vec3& x = s.pos[i];
      const double ground = m.terrain ? m.ground.height(x.x(), x.y()) : 0.0;
      if (!(x.z() - ground > m.size)) {
        c->dropped = true;
        return;
      }
    }
    c->payload.go(object_center(m, s, 0), s.steps, !c->started);
    c->body.go(body_center_of_mass(m, s), s.steps, !c->started);
    c->started = true;
  };
  loss.value = [&m, c](const State&) {
    const double p = c->payload.value(m), b = c->body.value(m);
    c->body_lesser = b < p;
    return std::min(p, b);
  };
  loss.adjoint = [&m, c](const State& s, Rows& d) {
    return (c->body_lesser ? c->body : c->payload).adjoint(m, s, d);
  };
  loss.branches = [c] {
    return signature({double(c->payload.from), double(c->payload.to), double(c->body_lesser)});
  };
  return loss;
}

// push: the box's travel from the first state after settling to the last (see_push).
TrajectoryLoss push_loss(const Model& m) {
  auto box = std::make_shared<Travel>();
  if (m.object_count() > 0) box->begin = m.object_begin[0], box->end = m.object_begin[1];
  TrajectoryLoss loss;
  loss.see = [&m, box](const State& s) {
    if (!s.settled || m.object_count() == 0) return;
    box->go(object_center(m, s, 0), s.steps, box->from < 0);
  };
  loss.value = [&m, box](const State&) { return box->value(m); };
  loss.adjoint = [&m, box](const State& s, Rows& d) { return box->adjoint(m, s, d); };
  loss.branches = [box] { return signature({double(box->from), double(box->to)}); };
  return loss;
}

}  // namespace

TrajectoryLoss task_loss(const Model& m) {
  switch (m.def.task) {
    case Task::kWalk:
      return final_loss(m, walk_score_of);
    case Task::kJump:
      return jump_loss(m);
    case Task::kTurn:
      return turn_loss(m);
    case Task::kRough:
    case Task::kObstacles:
      return final_loss(m, horizontal_score_of);
    case Task::kClimb:
      return final_loss(m, climb_score_of);
    case Task::kSlope:
      return final_loss(m, slope_score_of);
    case Task::kCarry:
      return carry_loss(m);
    case Task::kPush:
      return push_loss(m);
  }
  throw std::invalid_argument(std::string("gradient: task ") + to_string(m.def.task) +
                              " has no loss");
}

}  // namespace plastivox::grad
