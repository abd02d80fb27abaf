// The frame channels tables and the functions that go through them.
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "plastivox/environment.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"

namespace plastivox {
namespace {

// A control channel: a Frame member as doubles (Eigen's fixed-size vectors are plain arrays
// of doubles, x, y, z, so a vector of them is one flat array), filled by capture_control.
template <class T, std::vector<T> Frame::*kMember>
FrameField channel(const char* name, const char* python, const char* state_field) {
  static_assert(sizeof(T) % sizeof(double) == 0);
  return {name,
          python,
          state_field,
          static_cast<int>(sizeof(T) / sizeof(double)),
          {0, 1, 2, 3},
          [](const Frame& fr) { return reinterpret_cast<const double*>((fr.*kMember).data()); },
          [](Frame& fr, size_t voxels) { (fr.*kMember).resize(voxels); },
          nullptr};
}

}  // namespace

const std::vector<FrameField> kFrameFields = PLASTIVOX_FRAME_CHANNELS(PLASTIVOX_STATE_FIELDS);

const std::vector<FrameField> kControlFrameFields = {
    channel<double, &Frame::actuation>("actuation", "actuation", "actuation"),
    channel<double, &Frame::touch>("touch", "touch", "touch"),
    channel<double, &Frame::floor_force>("floor_force", "floor_force", "floor_force"),
    channel<double, &Frame::strain>("strain", "strain", "strain"),
    channel<double, &Frame::stress>("stress", "stress", "stress"),
    channel<double, &Frame::pressure>("pressure", "pressure", "pressure"),
    channel<Vec3, &Frame::velocity>("velocity", "velocity", "velocity"),
    channel<Vec3, &Frame::up>("up", "up", "up"),
};

namespace {

// The kSensorFields row a control channel copies; null for the signal.
const SensorField* sensor_of(const FrameField& f) {
  for (const SensorField& s : kSensorFields)
    if (std::strcmp(s.name, f.state_field) == 0) return &s;
  return nullptr;
}

}  // namespace

const char* frame_field_unit(const FrameField& f) {
  for (const FrameField& c : kControlFrameFields)
    if (std::strcmp(c.name, f.name) == 0) {
      const SensorField* s = sensor_of(c);
      return s ? s->unit : "1";
    }
  return state_field(f.state_field).unit;
}

void capture_control(Simulator& sim, Frame& frame) {
  const std::span<const double> signal = std::as_const(sim).actuation();
  const size_t n = signal.size();
  const Sensors sensors = sim.sensors();
  for (const FrameField& f : kControlFrameFields) {
    const SensorField* s = sensor_of(f);
    const std::span<const double> v = s ? sensors.read(s->id) : signal;
    f.resize(frame, n);
    std::memcpy(const_cast<double*>(f.values(frame)), v.data(), v.size() * sizeof(double));
  }
}

Frame capture_frame(const State& s) {
  Frame frame;
  frame.time = s.time;
  frame.step = s.steps;
  for (const FrameField& f : kFrameFields) f.copy(s, frame);
  return frame;
}

std::vector<double> frame_channel(const std::vector<Frame>& frames, const FrameField& f) {
  std::vector<double> out;
  if (!frames.empty()) out.reserve(frames.size() * frames.front().pos.size() * f.width);
  for (const Frame& frame : frames) {
    const double* v = f.values(frame);
    const size_t voxels = frame.pos.size();
    for (size_t i = 0; i < voxels; ++i)
      for (int k = 0; k < f.width; ++k) out.push_back(v[i * f.width + f.order[k]]);
  }
  return out;
}

void set_frame_channel(std::vector<Frame>& frames, const FrameField& f, size_t voxels,
                       const double* values) {
  for (Frame& frame : frames) {
    f.resize(frame, voxels);
    double* v = const_cast<double*>(f.values(frame));  // frame is ours to change
    for (size_t i = 0; i < voxels; ++i)
      for (int k = 0; k < f.width; ++k) v[i * f.width + f.order[k]] = *values++;
  }
}

std::vector<uint8_t> floor_contact(const Frame& frame, bool floor, const HeightField* ground) {
  std::vector<uint8_t> touching(frame.pos.size(), 0);
  for (size_t i = 0; floor && i < frame.pos.size(); ++i) {
    const Vec3& x = frame.pos[i];
    const double r = 0.5 * frame.size[i];
    const double pen = ground ? ground->penetration(x.x(), x.y(), x.z(), r) : r - x.z();
    touching[i] = pen > 0.0 ? 1 : 0;
  }
  return touching;
}

}  // namespace plastivox
