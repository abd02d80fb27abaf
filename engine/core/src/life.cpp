#include "plastivox/life.hpp"

#include <deque>
#include <stdexcept>
#include <string>
#include <utility>

#include "plastivox/state.hpp"

namespace plastivox {
namespace {

void check_times(const std::vector<double>& times, double duration) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] >= 0 && times[k] <= duration + 1e-12))
      throw std::invalid_argument("time " + std::to_string(times[k]) +
                                  " s is outside the life [0, " + std::to_string(duration) + "] s");
    if (k > 0 && times[k] < times[k - 1])
      throw std::invalid_argument("frame times must be ascending");
  }
}

}  // namespace

FrameSource simulated_frames(std::shared_ptr<const Model> model, bool control) {
  return [model = std::move(model), control](const std::vector<double>& times,
                                             const FrameSink& sink, const ProgressFn& progress) {
    const Model& m = *model;
    check_times(times, m.def.duration);
    // A frame at or after the settle time waits here until the life has settled (it settles
    // on the first step past the settle time), so each goes out with the centre of mass the
    // finished life reports.
    std::deque<LifeFrame> waiting;
    bool stopped = false;
    auto hand_over = [&](bool settled, const Vec3& com_settled, bool finished) {
      while (!stopped && !waiting.empty() &&
             (finished || settled || waiting.front().frame.time < m.def.settle_time)) {
        LifeFrame f = std::move(waiting.front());
        waiting.pop_front();
        f.settled = settled;
        f.com_settled = settled ? com_settled : Vec3::Zero();
        stopped = !sink(std::move(f));
      }
    };
    SimOptions options;
    options.frame_times = times;
    options.progress = progress;
    options.record_control = control;
    options.on_frame = [&](const State& s, Frame&& frame) {
      waiting.push_back(LifeFrame{std::move(frame), false, Vec3::Zero()});
      hand_over(s.settled, s.com_settled, false);
      return !stopped;
    };
    const SimResult r = simulate(m, options);
    hand_over(r.settled, r.com_settled, true);
    return r;
  };
}

FrameSource recorded_frames(std::shared_ptr<const Recording> recording, bool settled,
                            const Vec3& com_settled, double fitness, double settle_time) {
  return [=](const std::vector<double>& times, const FrameSink& sink, const ProgressFn&) {
    const std::vector<Frame>& frames = recording->frames;
    SimResult r;
    r.status = SimStatus::kFinished;
    r.settled = settled;
    r.com_settled = com_settled;
    r.fitness = fitness;
    size_t k = 0;
    for (size_t j = 0; j < times.size(); ++j) {
      if (j > 0 && times[j] < times[j - 1])
        throw std::invalid_argument("frame times must be ascending");
      while (k < frames.size() && frames[k].time < times[j] - 1e-9) ++k;
      if (k == frames.size()) {
        r.status = SimStatus::kUnstable;
        r.failure =
            "time " + std::to_string(times[j]) + " s is past the recording's last frame (t = " +
            (frames.empty() ? std::string("none") : std::to_string(frames.back().time)) + " s)";
        return r;
      }
      LifeFrame f;
      f.frame = frames[k];
      f.settled = settled && f.frame.time >= settle_time;
      f.com_settled = f.settled ? com_settled : Vec3::Zero();
      if (!sink(std::move(f))) break;
    }
    if (!frames.empty()) r.sim_time = frames.back().time;
    return r;
  };
}

}  // namespace plastivox
