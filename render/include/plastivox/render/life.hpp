// A life to draw: a robot under its physics, simulated (deterministically, so a champion's is
// exactly the life evolution scored), or frames recorded earlier. Reading one from a file is
// plastivox/render_files.hpp's (library plastivox_render_files); nothing here reads files.
// No GL here.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::render {

// A life as recorded (plastivox simulate --record life.h5): its frames and what was known of
// its settling and fitness.
struct RecordedFrames {
  Recording recording;  // frames in time order
  bool settled = false;
  Eigen::Vector3d com_settled = Eigen::Vector3d::Zero();  // m
  double fitness = 0;                                     // voxel lengths
};

struct LifeSource {
  std::string path;                   // the file read (names the life in messages)
  RobotDef robot;                     // the robot (lattice arrays: present, E0, alpha, phase)
  PhysicsDef physics;                 // what it is simulated under (treatment included)
  std::string label;                  // short caption: "stress · seed 3" or the robot's name
  std::vector<std::string> warnings;  // from reading a .vxa, one line each
  // A recorded life (`plastivox simulate --record life.h5`): its frames are drawn as
  // recorded, never simulated again (recorded_life() below). Null for every other source.
  std::shared_ptr<const RecordedFrames> recorded;
};

// A compiled robot with frames captured from its simulation.
struct Life {
  std::shared_ptr<const Model> model;
  std::vector<Frame> frames;    // one per requested time, in the order requested
  Eigen::Vector3d com_settled;  // centre of mass at the end of settling, m
  bool settled = false;         // the simulation reached physics.settle_time
  // The life ran to its end and its floor grade is `sank` (SimResult::sank): its last frames
  // show little or nothing above the floor, and a figure must say why.
  bool sank = false;
};

// Compiles the source and simulates it, capturing a frame at each requested time (s,
// ascending, each within [0, physics.duration]): the state at the first step whose time is
// >= the requested time, as the engine's own recording does. Stops after the last one.
// `progress` (optional) is called with the simulated fraction in [0, 1]. Throws
// RenderError if the simulation goes unstable before the last time.
Life simulate_life(const LifeSource& source, const std::vector<double>& times,
                   const std::function<void(double)>& progress = {});

// One captured frame as simulate_frames() hands it over, with what was known of settling
// then: exactly what the finished Life would say (a frame at or after the settle time is
// held back until the simulation has settled).
struct LifeFrame {
  Frame frame;
  bool settled = false;
  Eigen::Vector3d com_settled = Eigen::Vector3d::Zero();
};

// The compiled model of a source's robot under its physics, with recording off (frames are
// captured at requested times instead).
std::shared_ptr<const Model> compile_life_model(const LifeSource& source);

// simulate_life() for a model from compile_life_model(), handing each frame to `sink` as
// soon as it is known, in order, instead of keeping them: a caller can draw frame k while
// the simulation runs on towards frame k + 1. `sink` returns false to stop early. Throws as
// simulate_life() (after handing over the frames before the failure). Returns the
// simulation's summary (whole-life values only when the last time is the end of life).
SimResult simulate_frames(const LifeSource& source, const Model& model,
                          const std::vector<double>& times,
                          const std::function<bool(LifeFrame&&)>& sink,
                          const std::function<void(double)>& progress = {});

// For a recorded source: the frames simulate_frames() would hand over for `times` (s,
// ascending), taken from the recording instead: for each time the first recorded frame at
// or after it (a time within 1e-9 s of a frame counts as that frame's), with the life's
// settling as the recording holds it. Throws RenderError for a time past the last frame.
std::vector<LifeFrame> recorded_frames(const LifeSource& source, const std::vector<double>& times);

// simulate_life() for a recorded source, from recorded_frames(): no simulation.
Life recorded_life(const LifeSource& source, const std::vector<double>& times);

// Displacement of the centre of mass since settling, voxel lengths (zero before settling;
// z ignored under the xy fitness mode), the quantity fitness measures.
double displacement_so_far(const Life& life, const Frame& frame);

}  // namespace plastivox::render
