// A sampled life: every voxel's pose, size, stiffness and stimulus at fixed frame times,
// so the renderer and analysis can replay a simulation without re-running it; on request
// also its control channels: the actuation signal and the per-voxel sensors.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/state.hpp"

namespace plastivox {

struct Frame {
  double time = 0;   // s
  int64_t step = 0;  // simulation steps taken to reach this state
  // The State's RECORDED rows (PLASTIVOX_STATE_FIELDS), as the State holds them: pos (voxel
  // centre, m, world axes), orient (body-to-world rotation), stiffness (current E, Pa), size
  // (actuated edge length, m), stimulus (the treatment's, Pa; docs/plasticity.md); n each.
  PLASTIVOX_FRAME_MEMBERS(PLASTIVOX_STATE_FIELDS)
  // The control channels (kControlFrameFields), only when recorded (SimOptions::record_control;
  // empty otherwise). The sensors are those a controller reads at this state (docs/control.md).
  std::vector<double> actuation;          // the signal behind this frame's sizes, in [-1, 1] (n)
  std::vector<double> touch;              // sensor: 1 touching the floor or ground, else 0 (n)
  std::vector<double> floor_force;        // sensor: N (n)
  std::vector<double> strain;             // sensor: 1 (n)
  std::vector<double> stress;             // sensor: Pa (n)
  std::vector<double> pressure;           // sensor: Pa (n)
  std::vector<Eigen::Vector3d> velocity;  // sensor: m/s, world axes (n)
  std::vector<Eigen::Vector3d> up;        // sensor: the voxel's +z axis, world axes (n)
};

// The per-voxel channels of a Frame, described once: one for each RECORDED row of
// PLASTIVOX_STATE_FIELDS, generated from the list (FrameRow, plastivox/field_table.hpp, says
// what a channel holds). capture_frame, the recorded life file's writer and reader and the
// Python trajectory all go through this table, so a row made RECORDED in the list is
// recorded, written, read and handed to Python alike.
using FrameField = FrameRow<State, Frame>;
extern const std::vector<FrameField> kFrameFields;
// The control channels, a parallel table recorded only on request (so a default recording
// keeps its size): the actuation signal ("actuation") and every per-voxel sensor; here
// `state_field` names the kSensorFields row a channel copies ("actuation": the signal), and
// `copy` is null (capture_control fills them).
extern const std::vector<FrameField> kControlFrameFields;
// The unit of a channel of either table ("1" for the signal).
const char* frame_field_unit(const FrameField& f);

// One channel of `frames` as a flat array, frame-major: (frames, voxels, width), components
// in the field's order. Every frame holds `voxels` voxels.
std::vector<double> frame_channel(const std::vector<Frame>& frames, const FrameField& f);
// The inverse: fills the channel of each frame from such an array (frames are resized).
void set_frame_channel(std::vector<Frame>& frames, const FrameField& f, size_t voxels,
                       const double* values);

struct HeightField;  // environment.hpp

// Which voxels touch the ground in `frame` (1) and which do not (0), with the engine's own
// test: the voxel's actuated half-size reaches below z = 0 (or, given a height field, into
// it: HeightField::penetration), its tilt ignored, as the next step's contact sees it
// (engine/core/src/voxel_body.hpp, terrain.cpp). Obstacle boxes do not count. All 0 without
// a floor.
std::vector<uint8_t> floor_contact(const Frame& frame, bool floor,
                                   const HeightField* ground = nullptr);

struct Recording {
  double fps = 0;             // frames per simulated second
  std::vector<Frame> frames;  // in time order
  bool control = false;       // the frames carry the control channels (kControlFrameFields)
};

// Memory the frames of `voxels` voxels at `fps` frames per simulated second over a life of
// `duration` seconds take (a caller that copies them counts each copy): duration * fps + 2 frames
// (the first, the last and every 1/fps), each 10 doubles per voxel, 22 with the control channels.
// An upper bound: a step yields at most one frame.
inline double recording_bytes(int64_t voxels, double duration, double fps, bool control = false) {
  const double frames = duration * fps + 2;
  return frames * static_cast<double>(voxels) * ((control ? 22 : 10) * sizeof(double)) +
         frames * sizeof(Frame);
}

// Throws std::invalid_argument, one line naming `what` (the option or argument that asked
// for the frames), when a recording needs more than `limit_mb` MB of memory
// (Limits::recording_mb).
inline void check_recording_size(double bytes, const std::string& what, int64_t limit_mb) {
  const double limit = static_cast<double>(limit_mb) * (1 << 20);
  if (bytes <= limit) return;
  char text[320];
  std::snprintf(text, sizeof text,
                "%s: the recording would need about %.3g MB of memory, more than the limit of "
                "%.0f MB: record fewer frames per second or a shorter life, or raise the limit "
                "with the environment variable PLASTIVOX_MAX_RECORDING_MB",
                what.c_str(), bytes / (1 << 20), limit / (1 << 20));
  throw std::invalid_argument(text);
}

}  // namespace plastivox
