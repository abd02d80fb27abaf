// A life to draw: a robot under its physics with its frames on demand (plastivox/life.hpp):
// simulated (deterministically, so a champion's is exactly the life evolution scored) or
// recorded earlier. Whoever makes a LifeSource decides where its frames come from (reading
// one from a file is plastivox/render/files.hpp's); the renderer only asks for frames, so it
// never compiles or simulates anything itself. No GL here.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/io/life_file.hpp"  // RecordedLife
#include "plastivox/life.hpp"
#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::render {

struct LifeSource {
  std::string path;                    // the file read (names the life in messages)
  RobotDef robot;                      // the robot (lattice arrays: present, E0, alpha, phase)
  PhysicsDef physics;                  // what it is simulated under (treatment included)
  std::string label;                   // short caption: "stress · seed 3" or the robot's name
  std::vector<std::string> warnings;   // from reading a .vxa, one line each
  std::shared_ptr<const Model> model;  // the robot compiled under its physics
  FrameSource frames;                  // its frames: simulated, or read from `recorded`
  // The same frames with the actuation signal and sensors (the control channels, for colouring
  // by actuation): simulated with them, or as recorded (with them only when recorded with
  // them). Empty: the life has none to give.
  FrameSource frames_with_signal;
  // A recorded life (`plastivox simulate --record life.h5`): its frames are drawn as
  // recorded, never simulated again. Null for every other source.
  std::shared_ptr<const RecordedLife> recorded;
};

// The frames of a life at the requested times.
struct FrameSet {
  std::shared_ptr<const Model> model;
  std::vector<Frame> frames;    // one per requested time, in the order requested
  Eigen::Vector3d com_settled;  // centre of mass at the end of settling, m
  bool settled = false;         // the life reached physics.settle_time
  // The life ran to its end and its floor grade is `sank` (SimResult::sank): its last frames
  // show little or nothing above the floor, and a figure must say why.
  bool sank = false;
};

// source.frames() with the source's name in its errors: hands `sink` the frame at each
// requested time (s, ascending, each within [0, physics.duration]). Throws RenderError for
// a bad time, or when the life ends (unstable, or past a recording's end) before the last
// time, after handing over the frames before. Returns the life's summary.
SimResult take_frames(const LifeSource& source, const std::vector<double>& times,
                      const FrameSink& sink, const ProgressFn& progress = {});

// The FrameSet of take_frames(): every frame kept.
FrameSet take_frame_set(const LifeSource& source, const std::vector<double>& times,
                        const ProgressFn& progress = {});

// Displacement of the centre of mass since settling, voxel lengths (zero before settling;
// z ignored under the xy fitness mode), the quantity fitness measures.
double displacement_so_far(const FrameSet& life, const Frame& frame);

}  // namespace plastivox::render
