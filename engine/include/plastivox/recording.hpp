// A sampled life: every voxel's pose, size, stiffness and stimulus at fixed frame times,
// so the renderer and analysis can replay a simulation without re-running it.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plastivox {

struct Frame {
  double time = 0;                         // s
  int64_t step = 0;                        // simulation steps taken to reach this state
  std::vector<Eigen::Vector3d> pos;        // voxel centre, m, world frame (n)
  std::vector<Eigen::Quaterniond> orient;  // body-to-world rotation (n)
  std::vector<double> size;                // actuated edge length, m (n)
  std::vector<double> stiffness;           // current E, Pa (n)
  std::vector<double> stimulus;            // the treatment's stimulus, Pa (n; docs/plasticity.md)
};

// Which voxels touch the floor in `frame` (1) and which do not (0), with the engine's own
// test: the voxel's actuated half-size reaches below z = 0, its tilt ignored, as the next
// step's floor contact sees it (engine/src/voxel_body.hpp). All 0 without a floor.
inline std::vector<uint8_t> floor_contact(const Frame& frame, bool floor) {
  std::vector<uint8_t> touching(frame.pos.size(), 0);
  for (size_t i = 0; floor && i < frame.pos.size(); ++i)
    touching[i] = 0.5 * frame.size[i] - frame.pos[i].z() > 0.0 ? 1 : 0;
  return touching;
}

struct Recording {
  double fps = 0;             // frames per simulated second
  std::vector<Frame> frames;  // in time order
};

}  // namespace plastivox
