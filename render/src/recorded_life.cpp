// Drawing a recorded life (plastivox simulate --record life.h5) without simulating it again:
// the renderer's LifeSource / LifeFrame from the file (declared in plastivox/render/life.hpp).
#include <cmath>

#include "plastivox/evo/life_file.hpp"
#include "plastivox/render/life.hpp"
#include "plastivox/render/offscreen.hpp"  // RenderError

namespace plastivox::render {

LifeSource recorded_life_source(const std::string& path) {
  auto life = std::make_shared<evo::RecordedLife>(evo::read_life_file(path));
  if (life->recording.frames.empty()) throw RenderError(path + ": the recorded life has no frames");
  LifeSource src;
  src.path = path;
  src.robot = life->robot;
  src.physics = life->physics;
  // The life is as long as its recording (a life that went unstable ends early).
  src.physics.duration = std::min(src.physics.duration, life->recording.frames.back().time);
  src.label = "recorded · " + std::string(to_string(life->physics.treatment));
  if (life->seed) src.label += " · seed " + std::to_string(*life->seed);
  src.recorded = std::move(life);
  return src;
}

std::vector<LifeFrame> recorded_frames(const LifeSource& source, const std::vector<double>& times) {
  if (!source.recorded) throw RenderError(source.path + ": not a recorded life");
  const evo::RecordedLife& life = *source.recorded;
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
