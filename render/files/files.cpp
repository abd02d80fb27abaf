// Lives from files and the file-taking rendering commands (plastivox/render/files.hpp).
#include "plastivox/render/files.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/life.hpp"
#include "plastivox/render/offscreen.hpp"  // RenderError, write_png

namespace plastivox::render {

LifeSource simulated_life_source(const std::string& path, RobotDef robot, PhysicsDef physics,
                                 const std::string& label) {
  LifeSource src;
  src.path = path;
  src.robot = std::move(robot);
  src.physics = physics;
  src.label = label;
  try {
    src.model =
        std::make_shared<const Model>(compile(src.robot, src.physics, limits_from_environment()));
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ": " + e.what());
  }
  src.frames = simulated_frames(src.model);
  src.frames_with_signal = simulated_frames(src.model, true);
  return src;
}

LifeSource load_life_source(const std::string& path, int generation) {
  if (path.ends_with(".h5") && is_life_file(path)) return recorded_life_source(path);
  if (path.ends_with(".h5")) {
    const evo::ResultsFile results = evo::read_results(path);
    const evo::RunState& run = results.state;
    const evo::ChampionRecord& champion = evo::champion_at(run, generation, path);
    return simulated_life_source(
        path, evo::champion_robot(champion, generation < 0 ? run.generations_done : generation),
        run.config.physics,
        std::string(to_string(run.config.treatment)) + " · seed " +
            std::to_string(run.config.seed));
  }
  if (path.ends_with(".vxa") || path.ends_with(".json")) {
    LoadedRobot file = load_robot(path);
    const std::string label = file.robot.name.empty() ? path : file.robot.name;
    LifeSource src = simulated_life_source(path, std::move(file.robot), file.physics, label);
    src.warnings = std::move(file.warnings);
    return src;
  }
  throw InputError(path +
                   ": expected a robot (.json, .vxa), a results file or a recorded life (.h5)");
}

LifeSource recorded_life_source(const std::string& path) {
  RecordedLife life = read_life_file(path);
  if (life.result.recording.frames.empty())
    throw RenderError(path + ": the recorded life has no frames");
  PhysicsDef physics = life.physics;
  // The life is as long as its recording (a life that went unstable ends early).
  physics.duration = std::min(physics.duration, life.result.recording.frames.back().time);
  std::string label = "recorded · " + std::string(to_string(life.physics.treatment));
  if (life.seed) label += " · seed " + std::to_string(*life.seed);
  LifeSource src = simulated_life_source(path, life.robot, physics, label);
  auto recorded = std::make_shared<const RecordedLife>(std::move(life));
  // Drawn as recorded, never simulated: the frames come from the recording kept in
  // `recorded` (shared, not copied).
  const SimResult& r = recorded->result;
  src.frames = recorded_frames(std::shared_ptr<const Recording>(recorded, &r.recording), r.settled,
                               r.com_settled, r.fitness, physics.settle_time);
  src.frames_with_signal = src.frames;  // the signal is in its frames when it was recorded
  src.recorded = std::move(recorded);
  return src;
}

void render_frame_file(const std::string& source_path, double time, const FrameStyle& style,
                       const std::string& out, const LogFn& log) {
  check_output_path(out);
  check_render_target(style.width, style.height, style.samples);
  const LifeSource source = load_life_source(source_path);
  try {  // a time past the life's end is refused before "simulating ..." is said
    check_frame_times({time}, *source.model);
  } catch (const std::invalid_argument& e) {
    throw RenderError(source_path + ": " + e.what());
  }
  if (log) {
    for (const std::string& w : source.warnings) log("warning: " + w);
    const std::string at = "t = " + std::to_string(time) + " s";
    log(source.recorded ? "reading the recorded frame at " + at
                        : "simulating " + source_path + " to " + at);
  }
  write_png(out, render_frame(source, time, style), style.width, style.height);
}

VideoSummary render_video_file(const std::string& source, const FrameStyle& style,
                               const VideoJob& job, const std::string& out, const LogFn& log) {
  check_video_request(job, out);  // before reading anything
  check_render_target(style.width, style.height, style.samples);
  const LifeSource life = load_life_source(source);
  if (log)
    for (const std::string& w : life.warnings) log("warning: " + w);
  return render_video(life, style, job, out, log);
}

GalleryLayout render_gallery_file(const std::vector<std::string>& inputs, const GalleryStyle& style,
                                  const std::string& out, const LogFn& log) {
  check_gallery_request(style, inputs.size(), out);  // before any simulation
  std::vector<GalleryEntry> entries;
  for (size_t k = 0; k < inputs.size(); ++k) {
    GalleryEntry e;
    e.source = load_life_source(inputs[k]);
    if (log)
      log("gallery " + std::to_string(k + 1) + "/" + std::to_string(inputs.size()) + ": " +
          inputs[k] + " (" + e.source.label + ")");
    e.life = take_frame_set(e.source, gallery_times(e.source.physics, style));
    if (e.life.sank) e.source.label += " · SANK";  // as the study marks an audited champion
    entries.push_back(std::move(e));
  }
  return render_gallery(entries, style, out);
}

ShownLife show_life(const std::string& file, int generation, double fps,
                    const std::function<void(const std::string&)>& log) {
  const LifeSource source = load_life_source(file, generation);
  if (log)
    for (const std::string& w : source.warnings) log("warning: " + w);
  if (log && !source.recorded) {
    char what[96];
    std::snprintf(what, sizeof what, " (%g s at %g frames per second)", source.physics.duration,
                  fps);
    log("simulating " + file + what);
  }
  return show_life(source, fps);
}

std::vector<ViewerLink> write_report_lives(const std::vector<ReportChampion>& sources,
                                           const std::string& dir, double fps, int threads,
                                           const std::function<void(const std::string&)>& log) {
  std::vector<std::optional<ViewerLink>> links(sources.size());
  std::vector<std::string> failures(sources.size());
  parallel_for(sources.size(), threads, [&](size_t i) {
    const ShownLife shown = show_life(sources[i].file, sources[i].generation, fps);
    if (!shown.failure.empty())
      failures[i] = sources[i].file + ": no 3-D replay, " + shown.failure;
    else
      links[i] = write_report_life(dir, sources[i].id, shown.life());
  });
  std::vector<ViewerLink> out;
  for (size_t i = 0; i < links.size(); ++i) {
    if (links[i]) out.push_back(*links[i]);
    if (!failures[i].empty() && log) log(failures[i]);
  }
  remove_other_lives(dir, out);
  return out;
}

}  // namespace plastivox::render
