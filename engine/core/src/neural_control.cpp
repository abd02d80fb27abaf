// The neural controllers (distributed and central) and the controller a model asks for.
//
// Why plain loops: a network is a few dozen multiply-adds per voxel, small beside the physics
// (docs/benchmarks.md), and written once in scalar IEEE arithmetic (no FMA contraction, no
// library function: the activation is z / (1 + |z|)) it gives the same bits on every
// instruction set and machine. Each life runs on one thread, so threads and ranks cannot
// change them either.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "elementary.hpp"
#include "kernels.hpp"
#include "plastivox/base/names.hpp"
#include "plastivox/control.hpp"

namespace plastivox {
namespace {

constexpr Named<ControllerKind> kKindNames[] = {{ControllerKind::kSine, "sine"},
                                                {ControllerKind::kDistributed, "distributed"},
                                                {ControllerKind::kCentral, "central"}};

constexpr int kDistributedInputs = kLocalInputs + kFaces;  // 14
constexpr int kDistributedOutputs = 1 + kFaces;            // actuation, then one signal a face

// The activation: softsign, in (-1, 1), exact IEEE arithmetic.
inline double squash(double z) {
  return z / (1.0 + std::abs(z));
}

// One dense layer: out[k] = squash(b_k + sum_j w_kj in[j]) for k < outs; the weights are read
// from w row by row (bias first), and the pointer is returned past them.
const double* layer(const double* w, const double* in, int ins, double* out, int outs) {
  for (int k = 0; k < outs; ++k) {
    double z = *w++;
    for (int j = 0; j < ins; ++j) z += *w++ * in[j];
    out[k] = squash(z);
  }
  return w;
}

// Each voxel's local inputs, kLocalInputs a voxel (docs/control.md): its sine signal
// sin(2 pi (f t + phase_i)) (0 when f = 0), touch, strain, pressure / E (E its present
// stiffness), velocity / L (1/s, xyz) and the z component of its up vector.
void local_inputs(const Sensors& sensors, std::vector<double>& sine, std::vector<double>& out) {
  const Model& m = sensors.model();
  const State& s = sensors.state();
  const int n = m.n;
  sine.assign(n, 0.0);
  if (m.def.act_frequency != 0)
    kernels().sine(m.phase.data(), sine.data(), n, m.def.act_frequency * s.time);
  const std::span<const double> touch = sensors.read(Sensor::kTouch);
  const std::span<const double> strain = sensors.read(Sensor::kStrain);
  const std::span<const double> pressure = sensors.read(Sensor::kPressure);
  const std::span<const double> vel = sensors.read(Sensor::kVelocity);
  const std::span<const double> up = sensors.read(Sensor::kUp);
  const double inv_L = 1.0 / m.size;
  out.resize(static_cast<size_t>(n) * kLocalInputs);
  for (int i = 0; i < n; ++i) {
    double* x = &out[static_cast<size_t>(i) * kLocalInputs];
    x[0] = sine[i];
    x[1] = touch[i];
    x[2] = strain[i];
    x[3] = pressure[i] / s.stiffness[i];
    for (int c = 0; c < 3; ++c) x[4 + c] = vel[3 * i + c] * inv_L;
    x[7] = up[3 * i + 2];
  }
}

// The same network in every voxel. Inputs: the voxel's local inputs, then the signal each
// face neighbour sent towards it at the previous control call (0 where there is none, and at
// the first call). Outputs: the voxel's actuation and one signal towards each face.
class DistributedController final : public Controller {
 public:
  explicit DistributedController(const Model& m) : def_(m.controller) {
    // The neighbour across each face, from the bond slots (-1 where none).
    neighbour_.assign(static_cast<size_t>(m.n) * kFaces, -1);
    for (int i = 0; i < m.n; ++i)
      for (int f = 0; f < kFaces; ++f) {
        const int b = m.voxel_bonds[i][f];
        if (b >= 0) neighbour_[i * kFaces + f] = m.bond_a[b] == i ? m.bond_b[b] : m.bond_a[b];
      }
    reset();
  }

  void reset() override { sent_.assign(neighbour_.size(), 0.0); }

  void act(const Sensors& sensors, std::span<double> actuation) override {
    local_inputs(sensors, sine_, local_);
    const int n = sensors.model().n, h = def_.hidden;
    std::vector<double> next(sent_.size());
    double x[kDistributedInputs], hid[kMaxHidden], out[kDistributedOutputs];
    for (int i = 0; i < n; ++i) {
      std::copy_n(&local_[static_cast<size_t>(i) * kLocalInputs], kLocalInputs, x);
      // From the neighbour across face f: what it sent across its opposite face (f ^ 1).
      for (int f = 0; f < kFaces; ++f) {
        const int j = neighbour_[i * kFaces + f];
        x[kLocalInputs + f] = j >= 0 ? sent_[j * kFaces + (f ^ 1)] : 0.0;
      }
      const double* w = def_.weights.data();
      if (h > 0) {
        w = layer(w, x, kDistributedInputs, hid, h);
        layer(w, hid, h, out, kDistributedOutputs);
      } else {
        layer(w, x, kDistributedInputs, out, kDistributedOutputs);
      }
      actuation[i] = out[0];
      std::copy_n(out + 1, kFaces, &next[static_cast<size_t>(i) * kFaces]);
    }
    sent_.swap(next);
  }

 private:
  ControllerDef def_;
  std::vector<int> neighbour_;  // n x 6 voxel indices
  std::vector<double> sent_;    // n x 6 signals sent at the last call, one per face
  std::vector<double> sine_, local_;
};

// One network: a whole-body layer of `hidden` units over the body inputs (centre-of-mass
// velocity / L, sin and cos of 2 pi phase, the fraction of voxels touching), then a head,
// the same in every voxel, from that layer and the voxel's local inputs to its actuation.
class CentralController final : public Controller {
 public:
  explicit CentralController(const Model& m) : def_(m.controller) {}

  void act(const Sensors& sensors, std::span<double> actuation) override {
    const Model& m = sensors.model();
    const int n = m.n, h = def_.hidden;
    local_inputs(sensors, sine_, local_);
    const std::span<const double> com = sensors.read(Sensor::kComVelocity);
    const double phase = sensors.read(Sensor::kPhase)[0];
    const std::span<const double> touch = sensors.read(Sensor::kTouch);
    double touching = 0;
    for (int i = 0; i < n; ++i) touching += touch[i];
    const double body[kBodyInputs] = {com[0] / m.size,   com[1] / m.size,          com[2] / m.size,
                                      sin_cycles(phase), sin_cycles(phase + 0.25), touching / n};
    double in[kMaxHidden + kLocalInputs];
    const double* head = layer(def_.weights.data(), body, kBodyInputs, in, h);
    for (int i = 0; i < n; ++i) {
      std::copy_n(&local_[static_cast<size_t>(i) * kLocalInputs], kLocalInputs, in + h);
      layer(head, in, h + kLocalInputs, &actuation[i], 1);
    }
  }

 private:
  ControllerDef def_;
  std::vector<double> sine_, local_;
};

}  // namespace

const char* to_string(ControllerKind k) {
  return name_in(kKindNames, k);
}

ControllerKind parse_controller_kind(const std::string& s) {
  if (const auto k = value_in(kKindNames, s)) return *k;
  throw std::invalid_argument("'" + s + "' is not a controller (use " + choices_in(kKindNames) +
                              ")");
}

int weight_count(ControllerKind kind, int hidden) {
  switch (kind) {
    case ControllerKind::kSine:
      return 0;
    case ControllerKind::kDistributed:
      if (hidden < 0 || hidden > kMaxHidden) return -1;
      return hidden == 0 ? kDistributedOutputs * (1 + kDistributedInputs)
                         : hidden * (1 + kDistributedInputs) + kDistributedOutputs * (1 + hidden);
    case ControllerKind::kCentral:
      if (hidden < 1 || hidden > kMaxHidden) return -1;
      return hidden * (1 + kBodyInputs) + 1 + hidden + kLocalInputs;
  }
  return -1;
}

void validate(const ControllerDef& c) {
  const auto fail = [](const std::string& field, const std::string& what) {
    throw std::invalid_argument("controller." + field + ": " + what);
  };
  if (c.every < 1)
    fail("every", "the control rate must be >= 1 step, got " + std::to_string(c.every));
  const int count = weight_count(c.kind, c.hidden);
  if (count < 0)
    fail("hidden", std::string("must be in [") + (c.kind == ControllerKind::kCentral ? "1" : "0") +
                       ", " + std::to_string(kMaxHidden) + "] for " + to_string(c.kind) + ", got " +
                       std::to_string(c.hidden));
  if (c.weights.size() != static_cast<size_t>(count))
    fail("weights", "expected " + std::to_string(count) + " numbers for " + to_string(c.kind) +
                        " with hidden " + std::to_string(c.hidden) + ", got " +
                        std::to_string(c.weights.size()));
  for (size_t k = 0; k < c.weights.size(); ++k)
    if (!std::isfinite(c.weights[k])) fail("weights[" + std::to_string(k) + "]", "not finite");
}

std::unique_ptr<Controller> make_controller(const Model& model) {
  switch (model.controller.kind) {
    case ControllerKind::kSine:
      return std::make_unique<SineController>();
    case ControllerKind::kDistributed:
      return std::make_unique<DistributedController>(model);
    case ControllerKind::kCentral:
      return std::make_unique<CentralController>(model);
  }
  throw std::invalid_argument("controller.kind: unknown");
}

}  // namespace plastivox
