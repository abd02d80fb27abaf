// A life's frames on demand: the one way every drawing (stills, videos, galleries, the 3-D
// viewer) gets the states it draws. Whoever knows where a life comes from makes its
// FrameSource: simulated_frames() runs the engine; recorded_frames() reads a recording. The
// renderer only calls the source, so it never simulates anything itself.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {

// One frame as a FrameSource hands it over, with what was known of settling then: exactly
// what the finished life says (a frame at or after the settle time is held back until the
// life has settled; one before it goes out "not settled").
struct SourcedFrame {
  Frame frame;
  bool settled = false;
  Vec3 com_settled = Vec3::Zero();  // m; zero when not settled
};

// Receives each frame in time order; returns false to stop the life there.
using FrameSink = std::function<bool(SourcedFrame&&)>;
using ProgressFn = std::function<void(double)>;  // the fraction of the life done, [0, 1]

// Hands `sink` the frame at each time in `times` (s, ascending, within the life), as soon as
// it is known: the first state at or after the time. Returns the life's summary (its
// whole-life values only when the last time is the end of life). A life that goes unstable
// before the last time hands over the frames before and returns with status kUnstable; the
// caller sees fewer frames than times. The life ends at its first step past the duration, so
// its last frame may be asked for by any time up to that step. Throws std::invalid_argument
// for times that are not ascending or lie outside the life: before simulating for one past
// duration + longest_step(), after it for one past the last step.
using FrameSource = std::function<SimResult(const std::vector<double>& times, const FrameSink& sink,
                                            const ProgressFn& progress)>;

// The longest step a life of `model` can take (s): its last state, the first past the
// duration, lies at most this far past it. The time step of its start without development;
// with development, of every voxel at the softest modulus it can reach.
double longest_step(const Model& model);

// Throws std::invalid_argument for times that are not ascending or lie outside the life
// [0, duration + longest_step()]: the check simulated_frames makes before simulating, for
// callers that want it before they say they simulate.
void check_frame_times(const std::vector<double>& times, const Model& model);

// Frames simulated from `model` (simulate() with SimOptions::frame_times and on_frame), with
// the control channels (the actuation signal and sensors) when `control` is set.
FrameSource simulated_frames(std::shared_ptr<const Model> model, bool control = false);

// Frames from a recording: for each time the first recorded frame at or after it (a time
// within 1e-9 s of a frame counts as that frame's), settled from `settle_time` on as the
// recording says. The summary has status kFinished (or kUnstable when a time lies past the
// last frame: the frames before are handed over), `settled`, `com_settled` and `fitness`.
FrameSource recorded_frames(std::shared_ptr<const Recording> recording, bool settled,
                            const Vec3& com_settled, double fitness, double settle_time);

}  // namespace plastivox
