// The neural controllers' call on the recording type (docs/gradients.md, "The controller"):
// the distributed and central networks of engine/core/src/neural_control.cpp, with their
// sensors (control.cpp, compute) and the Simulator's rate limit (simulator.cpp, step2), in the
// engine's order of operations, so that the replica computes the engine's bits (gradient()
// checks it at every snapshot). The weights are read through the shadow of
// Model::controller.weights, so their adjoints are the gradient's controller_weights.
//
// Included by gradient.cpp after its sin_cycles<Adj> (the derivative the series lacks).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "adj.hpp"
#include "develop_body.hpp"  // stimulus_lanes
#include "elementary.hpp"    // sin_cycles
#include "plastivox/control.hpp"
#include "plastivox/model.hpp"
#include "plastivox/state.hpp"
#include "workspace.hpp"

namespace plastivox::grad {

// |z| recorded: d|z|/dz = sign z (+1 at 0, where softsign's slope is 1 from either side).
inline Adj magnitude(Adj z) {
  return {std::abs(z.v), record(z.id, branch(z.v < 0) ? -1.0 : 1.0, -1, 0.0)};
}

// The activation, softsign: z / (1 + |z|), smooth (its slope 1 / (1 + |z|)^2).
inline Adj squash(Adj z) {
  return z / (1.0 + magnitude(z));
}

class NetworkReplica {
 public:
  explicit NetworkReplica(const Model& m) : m_(m) {
    neighbour_.assign(static_cast<size_t>(m.n) * kFaces, -1);
    for (int i = 0; i < m.n; ++i)
      for (int f = 0; f < kFaces; ++f) {
        const int b = m.voxel_bonds[i][f];
        if (b >= 0) neighbour_[f * m.n + i] = m.bond_a[b] == i ? m.bond_b[b] : m.bond_a[b];
      }
  }

  // One control call of the model's network, between the halves of a step (s.dt already the
  // step's dt, `dt` its node): writes s.actuation and, for the distributed network,
  // s.control_memory, then holds each signal within act_max_rate * every * dt of the last.
  void act(State& s, const Workspace& w, Adj dt) {
    const Model& m = m_;
    const int n = m.n;
    std::vector<Adj> held(n);
    for (int i = 0; i < n; ++i) held[i] = load(s.actuation.data(), i, Adj{});
    weight_ = 0;
    std::vector<Adj> u(n);
    if (m.controller.kind == ControllerKind::kDistributed)
      distributed(s, w, u);
    else
      central(s, w, u);
    const double rate = m.def.act_max_rate;
    for (int i = 0; i < n; ++i) {
      if (rate > 0) {  // std::clamp(u, held - most, held + most): a kink where it binds
        const Adj most = rate * m.controller.every * dt;
        const Adj lo = held[i] - most, hi = held[i] + most;
        u[i] = u[i] < lo ? lo : hi < u[i] ? hi : u[i];
      }
      put(s.actuation.data(), i, u[i]);
    }
  }

 private:
  // The next weight, in the order docs/control.md gives (unit by unit, bias first).
  Adj weight() { return load(m_.controller.weights.data(), weight_++, Adj{}); }

  // One dense layer (neural_control.cpp, layer): out[k n + i] = squash(b_k + sum_j w_kj
  // in[j n + i]), the sum in the order written.
  void layer(const std::vector<Adj>& in, int ins, std::vector<Adj>& out, int outs, int n) {
    out.resize(static_cast<size_t>(outs) * n);
    for (int k = 0; k < outs; ++k) {
      const Adj b = weight();
      Adj* z = &out[static_cast<size_t>(k) * n];
      std::fill(z, z + n, b);
      for (int j = 0; j < ins; ++j) {
        const Adj wj = weight();
        const Adj* x = &in[static_cast<size_t>(j) * n];
        for (int i = 0; i < n; ++i) z[i] = z[i] + wj * x[i];
      }
      for (int i = 0; i < n; ++i) z[i] = squash(z[i]);
    }
  }

  // The local inputs (neural_control.cpp, local_inputs; the sensors of control.cpp, compute),
  // rows of n: the sine, touch (0 or 1: no derivative), strain, pressure / E, velocity / L,
  // up_z.
  void local_inputs(const State& s, const Workspace& w, std::vector<Adj>& rows) const {
    const Model& m = m_;
    const int n = m.n;
    Adj* row[kLocalInputs];
    for (int r = 0; r < kLocalInputs; ++r) row[r] = &rows[static_cast<size_t>(r) * n];
    const Adj cycles = m.def.act_frequency * load(&s.time, 0, Adj{});
    const double inv_L = 1.0 / m.size;
    const double* mom = s.lin_mom.front().data();
    const double* q = s.orient.front().coeffs().data();  // x, y, z, w per voxel
    for (int i = 0; i < n; ++i) {
      row[0][i] =
          m.def.act_frequency != 0 ? sin_cycles(cycles + load(m.phase.data(), i, Adj{})) : Adj(0.0);
      const bool terrain = m.def.environment.terrain();  // control.cpp's touch
      const double pen = terrain ? terrain_penetration(m, s.pos[i], 0.5 * s.size[i])
                                 : 0.5 * s.size[i] - s.pos[i].z();
      row[1][i] = (m.def.floor || terrain) && pen > 0 ? 1.0 : 0.0;
      row[2][i] = stimulus_lanes<Adj>(w.views.develop, i, m, Treatment::kStrain);
      row[3][i] = stimulus_lanes<Adj>(w.views.develop, i, m, Treatment::kPressure) /
                  load(s.stiffness.data(), i, Adj{});
      for (int c = 0; c < 3; ++c) row[4 + c][i] = load(mom, 3 * i + c, Adj{}) / m.mass * inv_L;
      // Eigen's q * (0, 0, 1), z component: uv = q.vec x e_z = (qy, -qx, 0), doubled; then
      // 1 + w uv_z + (q.vec x uv)_z = 1 + (qx uv_y - qy uv_x), each step exact as Eigen's.
      const Adj qx = load(q, 4 * i, Adj{}), qy = load(q, 4 * i + 1, Adj{});
      const Adj uvx = qy + qy, nqx = -qx, uvy = nqx + nqx;
      row[7][i] = 1.0 + (qx * uvy - qy * uvx);
    }
  }

  // DistributedController::act: the local inputs, then what each face neighbour sent at the
  // last call (the memory's rows 1..6), one or two layers; the outputs are the memory.
  void distributed(State& s, const Workspace& w, std::vector<Adj>& u) {
    const Model& m = m_;
    const int n = m.n, inputs = kLocalInputs + kFaces;
    std::vector<Adj> in(static_cast<size_t>(inputs) * n), out;
    local_inputs(s, w, in);
    double* memory = s.control_memory.data();
    for (int f = 0; f < kFaces; ++f)
      for (int i = 0; i < n; ++i) {
        const int j = neighbour_[f * n + i];
        in[static_cast<size_t>(kLocalInputs + f) * n + i] =
            j >= 0 ? load(memory, (1 + (f ^ 1)) * n + j, Adj{}) : Adj(0.0);
      }
    if (m.controller.hidden > 0) {
      std::vector<Adj> hidden;
      layer(in, inputs, hidden, m.controller.hidden, n);
      layer(hidden, m.controller.hidden, out, 1 + kFaces, n);
    } else {
      layer(in, inputs, out, 1 + kFaces, n);
    }
    for (size_t k = 0; k < out.size(); ++k) put(memory, k, out[k]);
    std::copy_n(out.begin(), n, u.begin());
  }

  // CentralController::act: a whole-body layer over the centre of mass's velocity / L, the
  // sine's phase (sin and cos) and the fraction touching, then the head in every voxel.
  void central(const State& s, const Workspace& w, std::vector<Adj>& u) {
    const Model& m = m_;
    const int n = m.n, h = m.controller.hidden;
    std::vector<Adj> local(static_cast<size_t>(kLocalInputs) * n);
    local_inputs(s, w, local);
    const double* mom = s.lin_mom.front().data();
    Adj p[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < m.robot_n; ++i)
      for (int c = 0; c < 3; ++c) p[c] = p[c] + load(mom, 3 * i + c, Adj{});
    double touching = 0;
    for (int i = 0; i < n; ++i) touching += local[n + i].v;
    // The phase f t mod 1: the floor moves no derivative.
    const Adj cycles = m.def.act_frequency * load(&s.time, 0, Adj{});
    const Adj phase = cycles - std::floor(cycles.v);
    const double body_mass = m.robot_n * m.mass;
    std::vector<Adj> body = {p[0] / body_mass / m.size, p[1] / body_mass / m.size,
                             p[2] / body_mass / m.size, sin_cycles(phase),
                             sin_cycles(phase + 0.25),  touching / n};
    std::vector<Adj> z;
    layer(body, kBodyInputs, z, h, 1);
    Adj bias = weight();
    for (int k = 0; k < h; ++k) bias = bias + weight() * z[k];
    // The head: one unit over the local rows, the body part its bias.
    for (int i = 0; i < n; ++i) u[i] = bias;
    for (int j = 0; j < kLocalInputs; ++j) {
      const Adj wj = weight();
      for (int i = 0; i < n; ++i) u[i] = u[i] + wj * local[static_cast<size_t>(j) * n + i];
    }
    for (int i = 0; i < n; ++i) u[i] = squash(u[i]);
  }

  const Model& m_;
  std::vector<int> neighbour_;  // 6 rows of n voxel indices (-1: none)
  int weight_ = 0;
};

}  // namespace plastivox::grad
