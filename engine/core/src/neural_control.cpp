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

// One dense layer over every voxel at once: out[k][i] = squash(b_k + sum_j w_kj in[j][i]),
// k < outs, j < ins, i < n (each array one row of n a unit or input). The weights are read
// from w unit by unit, bias first; returns the pointer past them. Each voxel's sum is taken in
// the order written, whatever the vector width the compiler picks (lanes are voxels).
const double* layer(const double* w, const double* in, int ins, double* out, int outs, int n) {
  for (int k = 0; k < outs; ++k) {
    double* z = out + static_cast<size_t>(k) * n;
    std::fill(z, z + n, *w++);
    for (int j = 0; j < ins; ++j) {
      const double wj = *w++;
      const double* x = in + static_cast<size_t>(j) * n;
      for (int i = 0; i < n; ++i) z[i] += wj * x[i];
    }
    for (int i = 0; i < n; ++i) z[i] = squash(z[i]);
  }
  return w;
}

// Each voxel's local inputs (docs/control.md), rows of n in this order: its sine signal
// sin(2 pi (f t + phase_i)) (0 when f = 0), touch, strain, pressure / E (E its present
// stiffness), velocity / L (1/s; x, y, z) and the z component of its up vector. Fills the first
// kLocalInputs rows of `rows`.
void local_inputs(const Sensors& sensors, double* rows) {
  const Model& m = sensors.model();
  const State& s = sensors.state();
  const int n = m.n;
  const auto row = [&](int r) { return rows + static_cast<size_t>(r) * n; };
  std::fill(row(0), row(1), 0.0);
  if (m.def.act_frequency != 0)
    kernels().sine(m.phase.data(), row(0), n, m.def.act_frequency * s.time);
  const std::span<const double> touch = sensors.read(Sensor::kTouch);
  const std::span<const double> strain = sensors.read(Sensor::kStrain);
  const std::span<const double> pressure = sensors.read(Sensor::kPressure);
  const std::span<const double> vel = sensors.read(Sensor::kVelocity);
  const std::span<const double> up = sensors.read(Sensor::kUp);
  const double inv_L = 1.0 / m.size;
  std::copy(touch.begin(), touch.end(), row(1));
  std::copy(strain.begin(), strain.end(), row(2));
  for (int i = 0; i < n; ++i) {
    row(3)[i] = pressure[i] / s.stiffness[i];
    for (int c = 0; c < 3; ++c) row(4 + c)[i] = vel[3 * i + c] * inv_L;
    row(7)[i] = up[3 * i + 2];
  }
}

// The same network in every voxel. Inputs: the voxel's local inputs, then the signal each
// face neighbour sent towards it at the previous control call (0 where there is none, and at
// the first call). Outputs: the voxel's actuation and one signal towards each face.
class DistributedController final : public Controller {
 public:
  explicit DistributedController(const Model& m)
      : def_(m.controller), n_(m.n), max_rate_(m.def.act_max_rate) {
    // The neighbour across each face, from the bond slots (-1 where none).
    neighbour_.assign(static_cast<size_t>(n_) * kFaces, -1);
    for (int i = 0; i < n_; ++i)
      for (int f = 0; f < kFaces; ++f) {
        const int b = m.voxel_bonds[i][f];
        if (b >= 0) neighbour_[f * n_ + i] = m.bond_a[b] == i ? m.bond_b[b] : m.bond_a[b];
      }
    in_.resize(static_cast<size_t>(n_) * kDistributedInputs);
    hidden_.resize(static_cast<size_t>(n_) * def_.hidden);
  }

  double max_rate() const override { return max_rate_; }
  // The outputs of the last call (the signals in flight, and the actuation, which the next
  // call overwrites), kept in the State: controller_memory_size.
  size_t memory_size() const override { return controller_memory_size(def_, n_); }

  void act(const Sensors& sensors, std::span<double> actuation, std::span<double> memory) override {
    const int n = n_;
    double* out = memory.data();
    local_inputs(sensors, in_.data());
    // From the neighbour j across face f: what j sent across its opposite face (f ^ 1) at
    // the last call, still in the memory (row 1 + face).
    for (int f = 0; f < kFaces; ++f) {
      double* x = &in_[static_cast<size_t>(kLocalInputs + f) * n];
      const double* sent = &out[static_cast<size_t>(1 + (f ^ 1)) * n];
      const int* j = &neighbour_[static_cast<size_t>(f) * n];
      for (int i = 0; i < n; ++i) x[i] = j[i] >= 0 ? sent[j[i]] : 0.0;
    }
    const double* w = def_.weights.data();
    if (def_.hidden > 0) {
      w = layer(w, in_.data(), kDistributedInputs, hidden_.data(), def_.hidden, n);
      layer(w, hidden_.data(), def_.hidden, out, kDistributedOutputs, n);
    } else {
      layer(w, in_.data(), kDistributedInputs, out, kDistributedOutputs, n);
    }
    std::copy_n(out, n, actuation.begin());
  }

 private:
  ControllerDef def_;
  int n_;
  std::vector<int> neighbour_;  // 6 rows of n voxel indices
  // Rows of n: the inputs and the hidden units (scratch; the outputs are the memory:
  // actuation, then the signals sent across each face, which the next call reads).
  std::vector<double> in_, hidden_;
  double max_rate_;  // physics.act_max_rate
};

// One network: a whole-body layer of `hidden` units over the body inputs (centre-of-mass
// velocity / L, sin and cos of 2 pi phase, the fraction of voxels touching), then a head,
// the same in every voxel, from that layer and the voxel's local inputs to its actuation:
// u_i = squash((b + sum_k v_k z_k) + sum_j u_j local_j,i), the body part summed once.
class CentralController final : public Controller {
 public:
  explicit CentralController(const Model& m)
      : def_(m.controller),
        local_(static_cast<size_t>(m.n) * kLocalInputs),
        max_rate_(m.def.act_max_rate) {}
  double max_rate() const override { return max_rate_; }

  void act(const Sensors& sensors, std::span<double> actuation, std::span<double>) override {
    const Model& m = sensors.model();
    const int n = m.n, h = def_.hidden;
    local_inputs(sensors, local_.data());
    const std::span<const double> com = sensors.read(Sensor::kComVelocity);
    const double phase = sensors.read(Sensor::kPhase)[0];
    const double* touch = local_.data() + n;  // row 1
    double touching = 0;
    for (int i = 0; i < n; ++i) touching += touch[i];
    const double body[kBodyInputs] = {com[0] / m.size,   com[1] / m.size,          com[2] / m.size,
                                      sin_cycles(phase), sin_cycles(phase + 0.25), touching / n};
    double z[kMaxHidden];
    const double* w = layer(def_.weights.data(), body, kBodyInputs, z, h, 1);
    double bias = *w++;
    for (int k = 0; k < h; ++k) bias += *w++ * z[k];
    // The head, as one unit over the local rows with the body part as its bias.
    double head[1 + kLocalInputs] = {bias};
    std::copy_n(w, kLocalInputs, head + 1);
    layer(head, local_.data(), kLocalInputs, actuation.data(), 1, n);
  }

 private:
  ControllerDef def_;
  std::vector<double> local_;  // kLocalInputs rows of n
  double max_rate_;
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

std::string controller_text(const ControllerDef& c) {
  std::string s = to_string(c.kind);
  if (c.kind == ControllerKind::kSine)
    s += " (open loop)";
  else if (c.hidden == 0)
    s += ", no hidden layer";
  else
    s += ", " + std::to_string(c.hidden) + (c.hidden == 1 ? " hidden unit" : " hidden units");
  if (c.every > 1)
    s += ", every " + std::to_string(c.every) + " steps";
  else if (c.kind != ControllerKind::kSine)
    s += ", every step";
  return s;
}

size_t controller_memory_size(const ControllerDef& c, int voxels) {
  return c.kind == ControllerKind::kDistributed
             ? static_cast<size_t>(voxels) * static_cast<size_t>(kDistributedOutputs)
             : 0;
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
  if (c.kind == ControllerKind::kSine && c.hidden != 0)
    fail("hidden", "the sine has no network, expected 0, got " + std::to_string(c.hidden));
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
