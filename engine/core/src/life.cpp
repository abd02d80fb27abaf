#include "plastivox/life.hpp"

#include <algorithm>
#include <charconv>
#include <deque>
#include <stdexcept>
#include <string>
#include <utility>

#include "plastivox/state.hpp"

namespace plastivox {
namespace {

// The shortest text that reads back as t: a time and the life's end are told apart in the
// message however close they are.
std::string seconds(double t) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, t).ptr);
}

}  // namespace

// A life ends at its first step past the duration, so its last state lies up to one step
// after it: a time there is the life's (its last frame), one further is refused before
// anything is simulated.
void check_frame_times(const std::vector<double>& times, const Model& m) {
  const double duration = m.def.duration, end = duration + longest_step(m);
  for (size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] >= 0 && times[k] <= end))
      throw std::invalid_argument("time " + seconds(times[k]) + " s is outside the life [0, " +
                                  seconds(duration) + "] s (it ends at its first step past " +
                                  seconds(duration) + " s)");
    if (k > 0 && times[k] < times[k - 1])
      throw std::invalid_argument("frame times must be ascending");
  }
}

double longest_step(const Model& m) {
  // stable_dt only grows as moduli fall; without development they never change, and with it
  // none falls below e_min (or its own start, for one that does not develop).
  const double start = stable_dt(m, m.e0);
  if (m.def.treatment == Treatment::kNone || m.n == 0) return start;
  double low = m.def.e_min;
  for (const double e : m.e0) low = std::min(low, e);
  return std::max(start, stable_dt(m, std::vector<double>(m.n, low)));
}

FrameSource simulated_frames(std::shared_ptr<const Model> model, bool control) {
  return [model = std::move(model), control](const std::vector<double>& times,
                                             const FrameSink& sink, const ProgressFn& progress) {
    const Model& m = *model;
    check_frame_times(times, m);
    // A frame at or after the settle time waits here until the life has settled (it settles
    // on the first step past the settle time), so each goes out with the centre of mass the
    // finished life reports.
    std::deque<SourcedFrame> waiting;
    bool stopped = false;
    auto hand_over = [&](bool settled, const Vec3& com_settled, bool finished) {
      while (!stopped && !waiting.empty() &&
             (finished || settled || waiting.front().frame.time < m.def.settle_time)) {
        SourcedFrame f = std::move(waiting.front());
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
      waiting.push_back(SourcedFrame{std::move(frame), false, Vec3::Zero()});
      hand_over(s.settled, s.com_settled, false);
      return !stopped;
    };
    const SimResult r = simulate(m, options);
    hand_over(r.settled, r.com_settled, true);
    // A life that ran to its end (sunk ones too) has every state there is: a time past its
    // last step, within the bound check_times allows, is outside it.
    if (!stopped && r.sim_time > m.def.duration)
      for (const double t : times)
        if (t > r.sim_time)
          throw std::invalid_argument("time " + seconds(t) + " s is outside the life [0, " +
                                      seconds(r.sim_time) + "] s (its last step)");
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
      SourcedFrame f;
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
