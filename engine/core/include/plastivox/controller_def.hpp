// Which controller a robot runs, as plain data (a robot file's "controller", an evolution
// config's): the kind, the network's size, the control rate and the network's weights.
// docs/control.md describes each kind's inputs, outputs and the weights' order.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace plastivox {

enum class ControllerKind {
  kSine,         // today's open loop (the default): no weights
  kDistributed,  // one small network per voxel, the same weights everywhere
  kCentral,      // one network over whole-body inputs, with a per-voxel shared head
};
const char* to_string(ControllerKind k);  // "sine", "distributed", "central"
// The kind named s; throws std::invalid_argument listing the kinds.
ControllerKind parse_controller_kind(const std::string& s);

// What each network reads and writes (docs/control.md, "Neural controllers").
inline constexpr int kLocalInputs = 8;  // per voxel: sine, touch, strain, pressure/E, v/L, up_z
inline constexpr int kFaces = 6;        // face neighbours: -x, +x, -y, +y, -z, +z
inline constexpr int kBodyInputs = 6;   // central: com velocity / L, sin and cos of phase, touch
inline constexpr int kMaxHidden = 64;   // the largest hidden layer a file may ask for

struct ControllerDef {
  ControllerKind kind = ControllerKind::kSine;
  // Hidden units: distributed, 0 (the inputs feed the outputs) to kMaxHidden; central, 1 to
  // kMaxHidden (the whole-body layer). Ignored by sine.
  int hidden = 0;
  int every = 1;                // control rate: the controller runs every `every` steps (>= 1)
  std::vector<double> weights;  // weight_count() values, in the order docs/control.md gives

  bool is_default() const { return kind == ControllerKind::kSine && every == 1; }
  bool operator==(const ControllerDef&) const = default;
};

// How many weights a network of this kind and hidden size has (0 for sine); -1 when
// `hidden` is out of range for the kind.
int weight_count(ControllerKind kind, int hidden);

// How many values a controller of this kind remembers between calls for a body of `voxels`
// voxels (State::control_memory): the distributed network's outputs (the signals it sends to
// its neighbours), none for the others.
size_t controller_memory_size(const ControllerDef& c, int voxels);

// The controller in words, as reports state it: "sine (open loop)", "distributed, 4 hidden
// units, every step", "central, 1 hidden unit, every 2 steps", "distributed, no hidden
// layer, every step"; a sine run every k > 1 steps adds ", every k steps".
std::string controller_text(const ControllerDef& c);

// Throws std::invalid_argument naming the field ("controller.hidden: ...") when the kind's
// hidden size or the rate is out of range, or the weights are not weight_count() finite
// numbers.
void validate(const ControllerDef& c);

}  // namespace plastivox
