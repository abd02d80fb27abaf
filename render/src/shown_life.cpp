// The lives the viewer shows (plastivox/render/viewer.hpp): a recorded life as it was, or a
// life taken once from its source, with frames for the viewer and, from the same run, for a
// gallery.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "plastivox/life.hpp"
#include "plastivox/render/error.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/rules/life_rules.hpp"

namespace plastivox::render {

ViewerItem ShownLife::life() const {
  ViewerItem l = info;
  l.model = &model;
  l.recording = &recording;
  return l;
}

namespace {

// A life to show with its model and caption set; no frames yet.
ShownLife described(const LifeSource& source) {
  if (!source.model)
    throw RenderError(source.path + ": no life to draw (a LifeSource without a model)");
  ShownLife out;
  out.model = *source.model;
  out.info.label = source.label;
  out.info.treatment = to_string(source.physics.treatment);
  return out;
}

}  // namespace

ReportFrames report_life(const LifeSource& source, double fps, const std::vector<double>& times) {
  const PhysicsDef& def = source.physics;
  ReportFrames out;
  out.shown = described(source);
  ShownLife& shown = out.shown;
  if (!(fps > 0)) throw RenderError("report_life: fps must be > 0");
  for (size_t k = 0; k < times.size(); ++k)
    if (!(times[k] >= 0 && times[k] <= def.duration) || (k > 0 && times[k] < times[k - 1]))
      throw RenderError(source.path + ": frame times must ascend within the life [0, " +
                        std::to_string(def.duration) + "] s");

  // One list of frame times for the source: the viewer's (k / fps, then the first state past
  // the end, as the engine's own recording ends) and the caller's. Each wanted frame keeps
  // where it goes: >= 0 an index into `times`, -1 the viewer.
  std::vector<std::pair<double, int>> wanted;
  for (int64_t k = 0;; ++k) {
    const double t = static_cast<double>(k) / fps;
    if (t > def.duration) break;
    wanted.push_back({t, -1});
  }
  wanted.push_back({std::nextafter(def.duration, std::numeric_limits<double>::infinity()), -1});
  for (size_t k = 0; k < times.size(); ++k) wanted.push_back({times[k], static_cast<int>(k)});
  std::stable_sort(wanted.begin(), wanted.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });

  std::vector<double> all_times;
  for (const auto& w : wanted) all_times.push_back(w.first);
  shown.recording.fps = fps;
  out.frames.frames.resize(times.size());
  size_t taken = 0, extra = 0;
  int64_t last_viewer_step = -1;
  // The frames with the actuation signal where the source has them, so the viewer can colour
  // by it (a recorded life has it only when it was recorded with it).
  const FrameSource signal_frames =
      source.frames_with_signal ? source.frames_with_signal : source.frames;
  shown.recording.control = source.recorded ? source.recorded->result.recording.control
                                            : static_cast<bool>(source.frames_with_signal);
  SimResult r;
  try {
    r = signal_frames(
        all_times,
        [&](SourcedFrame&& f) {
          const int to = wanted[taken++].second;
          if (to >= 0) {
            out.frames.frames[to] = f.frame;
            extra += 1;
          } else if (f.frame.step != last_viewer_step) {  // one frame per state, as recorded
            last_viewer_step = f.frame.step;
            shown.recording.frames.push_back(std::move(f.frame));
          }
          return true;
        },
        {});
  } catch (const std::invalid_argument& e) {
    throw RenderError(source.path + ": " + e.what());
  }
  // A life that sinks through the floor is drawn to its end: the fall is what a reader needs
  // to see. Its fitness stays what the rule in force gives it (judge_life: 0 where sunk lives
  // are invalid); only a life that blew up is a failure here.
  if (source.model) judge_life(source.model->def, r);
  shown.info.settled = r.settled;
  shown.info.com_settled = r.com_settled;
  shown.info.fitness = r.fitness;
  if (r.status != SimStatus::kFinished && !r.sank)
    shown.failure = "simulation unstable: " + r.failure;
  out.frames.model = source.model;
  out.frames.settled = r.settled;
  out.frames.com_settled = r.com_settled;
  if (extra < times.size()) {
    out.frames.frames.clear();
    out.frames_failure = source.path +
                         ": the simulation went unstable at t = " + std::to_string(r.sim_time) +
                         " s (" + r.failure + ")";
  }
  return out;
}

ShownLife show_life(const LifeSource& source, double fps) {
  if (source.recorded) {
    ShownLife out = described(source);
    const SimResult& r = source.recorded->result;
    out.recording = r.recording;
    out.info.settled = r.settled;
    out.info.com_settled = r.com_settled;
    out.info.fitness = r.fitness;
    return out;
  }
  return report_life(source, fps, {}).shown;
}

}  // namespace plastivox::render
