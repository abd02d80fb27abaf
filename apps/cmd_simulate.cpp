// plastivox simulate: one robot, one life, a summary (text or JSON).
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/life_file.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/resolve_physics.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/io/sim_summary.hpp"
#include "plastivox/render/history_file.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "plastivox_version.hpp"

namespace plastivox::cli {
namespace {

// A non-negative number given to `option`; `what` names its unit and rule in the error.
double parse_non_negative(const std::string& s, const std::string& option, const char* what) {
  double v = 0;
  if (!read_number(s, v) || !(v >= 0))
    throw UsageError{option + " must be " + what + ", got '" + s + "'"};
  return v;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Writes the life's frames to `path`: a recorded life (.h5) or a voxcraft-viz history.
// The frames move into the file's record: a long recording is held once, not twice.
void write_recording(const std::string& path, const std::string& source, const RobotDef& robot,
                     const PhysicsDef& physics, const Model& model, SimResult& r) {
  if (path.ends_with(".history")) {
    render::write_history_file(path, model, r.recording);
    return;
  }
  RecordedLife life;
  life.source = source;
  life.robot = robot;
  life.physics = physics;
  Recording frames = std::move(r.recording);
  life.result = r;  // without the frames, which move
  life.result.recording = std::move(frames);
  write_life_file(path, life);
}

}  // namespace

int cmd_simulate(const Args& in) {
  Args args = in;
  const bool as_json = take_flag(args, "--json");
  const bool timed = take_flag(args, "--timings");
  const std::string treatment = take_option(args, "--treatment", "");
  const std::string task = take_option(args, "--task", "");
  const std::string preset = take_option(args, "--preset", "");
  const std::string duration = take_option(args, "--duration", "");
  const std::string overrides = take_option(args, "--physics", "");
  const std::string controller = take_option(args, "--controller", "");
  const std::string record = take_option(args, "--record", "");
  const std::string fps_text = take_option(args, "--fps", "");
  const bool record_control = take_flag(args, "--record-control");
  const std::string vxd = take_option(args, "--vxd", "");
  reject_unknown_options(args);
  if (args.size() > 1) throw UsageError{"expected at most one robot file"};
  if (!vxd.empty() && (args.size() != 1 || !args[0].ends_with(".vxa")))
    throw UsageError{
        "--vxd ROBOT.vxd goes with voxcraft-sim's base: plastivox simulate base.vxa --vxd "
        "robot.vxd"};
  if (!record.empty() && !record.ends_with(".h5") && !record.ends_with(".history"))
    throw UsageError{"--record " + record +
                     ": expected a recorded life (.h5) or a voxcraft-viz history (.history)"};
  if (record_control && !record.ends_with(".h5"))
    throw UsageError{
        "--record-control adds the actuation signal and the sensors to a recorded life: "
        "plastivox simulate ROBOT --record life.h5 --record-control"};
  if (!fps_text.empty() && record.empty())
    throw UsageError{
        "--fps sets the frame rate of --record: plastivox simulate ROBOT --record "
        "life.h5 --fps " +
        fps_text};
  double fps = 30;  // frames per simulated second of --record
  if (!fps_text.empty()) {
    fps = parse_non_negative(fps_text, "--fps",
                             "a number of frames per simulated second in (0, 10000]");
    if (!(fps > 0 && fps <= 10000)) throw UsageError{"--fps must be in (0, 10000]"};
  }
  // Command-line values are checked before any file is read (a bad one exits 2).
  std::optional<Treatment> treatment_given;
  std::optional<Task> task_given;
  try {
    if (!preset.empty()) physics_preset(preset);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--preset: ") + e.what()};
  }
  try {
    if (!treatment.empty()) treatment_given = parse_treatment(treatment);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--treatment: ") + e.what()};
  }
  try {
    if (!task.empty()) task_given = parse_task(task);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--task: ") + e.what()};
  }
  const double duration_s =
      duration.empty() ? 0.0
                       : parse_non_negative(duration, "--duration",
                                            "a number of seconds >= 0 (the life's length, at "
                                            "least the physics' settle_time, at most 1e4)");

  RobotDef robot;
  PhysicsDef physics;
  std::string source = "built-in demo walker";
  std::optional<double> vxa_density;  // a VXA file's own density, for the warning below
  if (args.empty()) {
    robot = demo_walker();
    physics = preset_gecco2018_code();
    physics.treatment = Treatment::kStress;
  } else {
    source = args[0];
    LoadedRobot file = load_robot(source, vxd);
    if (!vxd.empty()) source += " + " + vxd;
    for (const std::string& w : file.warnings)
      std::fprintf(stderr, "plastivox simulate: warning: %s\n", w.c_str());
    robot = std::move(file.robot);
    physics = file.physics;
    if (args[0].ends_with(".vxa")) vxa_density = file.physics.density;
  }
  // The life's physics by the one rule (docs/robot-format.md, "Resolving a run's physics"):
  // the file's, --preset, --physics, then --treatment, --task and --duration, which win.
  PhysicsRequest request;
  request.preset = preset;
  request.fields = overrides;
  request.where = overrides.empty() ? source : "--physics";
  request.treatment = treatment_given;
  request.task = task_given;
  if (!duration.empty()) request.duration = duration_s;
  physics = resolve_physics(physics, request);
  // Recording is not physics: frames are kept only in a file, at --fps. (An older physics
  // object names its rate as record_fps.)
  if (!overrides.empty()) {
    const nlohmann::json given = parse_json_input(overrides, "--physics", "--physics");
    if (given.contains("record_fps")) {
      const double asked = given["record_fps"].is_number() ? given["record_fps"].get<double>() : 0;
      if (record.empty())
        throw UsageError{
            "--physics: record_fps keeps frames only in a file: use plastivox "
            "simulate ROBOT --record life.h5 --fps " +
            number(asked) + " (or life.history)"};
      if (fps_text.empty()) fps = asked;
      if (!(fps > 0)) throw UsageError{"--physics: record_fps must be > 0 with --record"};
    }
  }

  if (!controller.empty())  // replaces the robot's own (docs/control.md)
    robot.controller = json_field::controller(parse_json_input(controller, "--controller"),
                                              "--controller", "controller", true);

  const Limits limits = limits_from_environment();
  Model model;
  try {  // validation and the life's bounds (docs/robot-format.md, "Limits"), naming the file
    model = compile(robot, physics, limits);
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": " + e.what());
  }
  StageTimings timings;
  SimOptions options;
  if (timed) options.timings = &timings;
  if (!record.empty()) {
    options.record_fps = fps;
    options.record_control = record_control;
    // Refused before the life is simulated, not when memory runs out. A recorded life is
    // held three times while it is written: the frames, the file's image in memory and its
    // sealed bytes (a history file's text is larger per frame but written as it goes).
    try {
      check_recording_size(3 * recording_bytes(model.n, physics.duration, fps, record_control),
                           "--fps", limits.recording_mb);
    } catch (const std::invalid_argument& e) {
      throw UsageError{e.what()};
    }
  }
  SimResult r = simulate(model, options);
  judge_life(physics, r);  // whether it counts (the exit status), the vertical rule's warning
  if (vxa_density) warn_vxa_density(r, source, *vxa_density, physics, robot.voxel_size);
  // Health warnings (a body pressed into or sunk through the floor: simulate()'s; a fitness
  // of vertical motion: judge_life's): on stderr always, and in the JSON.
  for (const std::string& w : r.warnings)
    std::fprintf(stderr, "plastivox simulate: warning: %s: %s\n", source.c_str(), w.c_str());

  const size_t frames = r.recording.frames.size();
  if (!record.empty()) write_recording(record, source, robot, physics, model, r);

  if (as_json) {
    std::string summary =
        sim_summary_json(r, physics, source, PLASTIVOX_VERSION, timed ? &timings : nullptr);
    if (!record.empty()) {  // what was recorded, in the same (sorted, indented) JSON
      nlohmann::json j = nlohmann::json::parse(summary);
      j["recording"] = {
          {"file", record},
          {"format", record.ends_with(".history") ? "voxcraft-viz history" : "plastivox-life"},
          {"fps", fps},
          {"frames", frames}};
      summary = j.dump(1);
    }
    std::printf("%s\n", summary.c_str());
  } else {
    std::printf("%s: %d voxels, treatment %s, task %s, %s\n", source.c_str(), r.voxels,
                to_string(physics.treatment), to_string(physics.task), to_string(r.status));
    std::printf("  fitness %.4f %s (dx %.4f, dy %.4f, dz %.4f voxel lengths)\n", r.fitness,
                task_info(physics.task).unit, r.displacement.x(), r.displacement.y(),
                r.displacement.z());
    std::printf("  %s: %s\n", r.success ? "success" : "no success",
                task_info(physics.task).criterion);
    std::printf(
        "  floor: %s, %.3g voxel lengths deep at the deepest; vertical share of "
        "fitness %.3f\n",
        to_string(r.floor_health), r.floor_depth, r.vertical_share);
    std::printf("  stiffness change: mean %+.3f %%, mean |change| %.3f %%\n",
                100 * r.stiffness_change_mean, 100 * r.stiffness_change_abs_mean);
    std::printf("  %lld steps, dt %.3g s, %.2f s wall (%.3g voxel-steps/s)\n",
                static_cast<long long>(r.steps), r.dt_initial, r.wall_seconds,
                r.wall_seconds > 0 ? r.voxels * r.steps / r.wall_seconds : 0.0);
    if (timed) {
      std::printf("  stages (wall time of %lld steps):\n", static_cast<long long>(timings.steps));
      for (const StageName& s : kStageNames)
        std::printf("    %-16s %8.3f s  %5.1f %%\n", s.name, timings.*s.seconds,
                    timings.total() > 0 ? 100 * timings.*s.seconds / timings.total() : 0.0);
    }
    if (!record.empty())
      std::printf("  recorded %s at %g fps to %s\n",
                  count_of(static_cast<long long>(frames), "frame").c_str(), fps, record.c_str());
  }
  if (r.status != SimStatus::kFinished) {
    std::fprintf(stderr, "plastivox simulate: %s: %s: %s\n", source.c_str(),
                 r.sank ? "life invalid" : "simulation unstable", r.failure.c_str());
    return 3;
  }
  return 0;
}

}  // namespace plastivox::cli
