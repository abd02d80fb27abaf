// Drawing a recorded life (plastivox simulate --record life.h5) without simulating it again:
// its frames as the renderer's LifeFrames (declared in plastivox/render/life.hpp).
#include <cmath>

#include "plastivox/render/error.hpp"
#include "plastivox/render/life.hpp"

namespace plastivox::render {

std::vector<LifeFrame> recorded_frames(const LifeSource& source, const std::vector<double>& times) {
  if (!source.recorded) throw RenderError(source.path + ": not a recorded life");
  const RecordedFrames& life = *source.recorded;
  const std::vector<Frame>& frames = life.recording.frames;
  std::vector<LifeFrame> out;
  out.reserve(times.size());
  size_t k = 0;
  for (size_t j = 0; j < times.size(); ++j) {
    if (j > 0 && times[j] < times[j - 1])
      throw RenderError("recorded_frames: times must be ascending");
    while (k < frames.size() && frames[k].time < times[j] - 1e-9) ++k;
    if (k == frames.size())
      throw RenderError(source.path + ": time " + std::to_string(times[j]) +
                        " s is past the recording's last frame (t = " +
                        std::to_string(frames.back().time) + " s)");
    LifeFrame f;
    f.frame = frames[k];
    // As simulate_frames hands them over: settled from the settle time on.
    f.settled = life.settled && f.frame.time >= source.physics.settle_time;
    f.com_settled = f.settled ? life.com_settled : Eigen::Vector3d::Zero();
    out.push_back(std::move(f));
  }
  return out;
}

Life recorded_life(const LifeSource& source, const std::vector<double>& times) {
  Life life;
  life.model = compile_life_model(source);
  for (LifeFrame& f : recorded_frames(source, times)) {
    life.settled = f.settled;
    life.com_settled = f.com_settled;
    life.frames.push_back(std::move(f.frame));
  }
  return life;
}

}  // namespace plastivox::render
