#include "plastivox/render/life.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "plastivox/render/error.hpp"
#include "plastivox/state.hpp"

namespace plastivox::render {

SimResult take_frames(const LifeSource& source, const std::vector<double>& times,
                      const FrameSink& sink, const ProgressFn& progress) {
  if (!source.frames || !source.model)
    throw RenderError(source.path + ": no life to draw (a LifeSource without frames)");
  size_t taken = 0;
  bool stopped = false;
  SimResult r;
  try {
    r = source.frames(
        times,
        [&](SourcedFrame&& f) {
          taken += 1;
          stopped = !sink(std::move(f));
          return !stopped;
        },
        progress);
  } catch (const std::invalid_argument& e) {
    throw RenderError(source.path + ": " + e.what());
  }
  if (!stopped && taken < times.size()) {
    if (source.recorded) throw RenderError(source.path + ": " + r.failure);
    throw RenderError(source.path + ": the simulation went unstable at t = " +
                      std::to_string(r.sim_time) + " s (" + r.failure + ")");
  }
  return r;
}

FrameSet take_frame_set(const LifeSource& source, const std::vector<double>& times,
                        const ProgressFn& progress) {
  FrameSet life;
  life.model = source.model;
  life.frames.reserve(times.size());
  const SimResult r = take_frames(
      source, times,
      [&](SourcedFrame&& f) {
        // Every frame leaves with the final settling state but the ones before settling,
        // which leave with "not settled" and do not use it.
        life.settled = f.settled;
        life.com_settled = f.com_settled;
        life.frames.push_back(std::move(f.frame));
        return true;
      },
      progress);
  life.sank = r.sank;
  return life;
}

double displacement_so_far(const FrameSet& life, const Frame& frame) {
  const Model& m = *life.model;
  if (!life.settled || frame.time < m.def.settle_time) return 0;
  // The robot's centre of mass: the free objects' voxels that follow it are not the robot's.
  return displacement_since_settling(m, life.com_settled, center_of_mass(frame.pos, m.robot_n))
      .norm();
}

}  // namespace plastivox::render
