// A sampled life: every voxel's pose, size, stiffness and stimulus at fixed frame times,
// so the renderer and analysis can replay a simulation without re-running it.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plastivox {

struct Frame {
  double time = 0;                         // s
  std::vector<Eigen::Vector3d> pos;        // voxel centre, m, world frame (n)
  std::vector<Eigen::Quaterniond> orient;  // body-to-world rotation (n)
  std::vector<double> size;                // actuated edge length, m (n)
  std::vector<double> stiffness;           // current E, Pa (n)
  std::vector<double> stimulus;            // stress or pressure, Pa (n)
};

struct Recording {
  double fps = 0;             // frames per simulated second
  std::vector<Frame> frames;  // in time order
};

}  // namespace plastivox
