#include "plastivox/render/life.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/limits.hpp"
#include "plastivox/render/error.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::render {

std::shared_ptr<const Model> compile_life_model(const LifeSource& source) {
  return std::make_shared<const Model>(
      compile(source.robot, source.physics, limits_from_environment()));
}

SimResult simulate_frames(const LifeSource& source, const Model& model,
                          const std::vector<double>& times,
                          const std::function<bool(LifeFrame&&)>& sink,
                          const std::function<void(double)>& progress) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] >= 0 && times[k] <= source.physics.duration + 1e-12))
      throw RenderError(source.path + ": time " + std::to_string(times[k]) +
                        " s is outside the life [0, " + std::to_string(source.physics.duration) +
                        "] s");
    if (k > 0 && times[k] < times[k - 1])
      throw RenderError("simulate_frames: times must be ascending");
  }
  // A frame at or after the settle time waits here until the simulation has settled (it
  // settles on the first step past the settle time), so each goes out with the centre of
  // mass the finished life reports.
  std::deque<LifeFrame> waiting;
  size_t taken = 0;
  bool stopped = false;
  auto hand_over = [&](bool settled, const Eigen::Vector3d& com_settled, bool finished) {
    while (!stopped && !waiting.empty() &&
           (finished || settled || waiting.front().frame.time < model.def.settle_time)) {
      LifeFrame f = std::move(waiting.front());
      waiting.pop_front();
      f.settled = settled;
      f.com_settled = settled ? com_settled : Eigen::Vector3d::Zero();
      stopped = !sink(std::move(f));
    }
  };
  SimOptions options;
  options.frame_times = times;
  options.progress = progress;
  options.on_frame = [&](const State& s) {
    waiting.push_back(LifeFrame{capture_frame(s), false, Eigen::Vector3d::Zero()});
    taken += 1;
    hand_over(s.settled, s.com_settled, false);
    return !stopped;
  };
  const SimResult r = simulate(model, options);
  hand_over(r.settled, r.com_settled, true);
  if (!stopped && taken < times.size() && r.status == SimStatus::kUnstable)
    throw RenderError(source.path + ": the simulation went unstable at t = " +
                      std::to_string(r.sim_time) + " s (" + r.failure + ")");
  return r;
}

Life simulate_life(const LifeSource& source, const std::vector<double>& times,
                   const std::function<void(double)>& progress) {
  Life life;
  life.model = compile_life_model(source);
  life.frames.reserve(times.size());
  const SimResult r = simulate_frames(
      source, *life.model, times,
      [&](LifeFrame&& f) {
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

double displacement_so_far(const Life& life, const Frame& frame) {
  const Model& m = *life.model;
  if (!life.settled || frame.time < m.def.settle_time) return 0;
  return displacement_since_settling(m, life.com_settled, center_of_mass(frame.pos)).norm();
}

}  // namespace plastivox::render
