// plastivox export: a champion from an evolution results file, a robot file or (with --demo
// NAME) a built-in example robot, as a robot file in the VXA dialect of the authors' simulator
// (.vxa) or the project's own format (.json), or with --format voxcraft as voxcraft-sim's
// base.vxa + robot.vxd.
#include <cstdio>
#include <string>

#include "cli.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/io/voxcraft.hpp"

namespace plastivox::cli {
namespace {

// Writes robot with physics as .vxa (printing the writer's warnings) or .json.
void write_robot(const std::string& out, const RobotDef& robot, const PhysicsDef& physics) {
  std::vector<std::string> warnings;
  save_robot(out, robot, physics, &warnings);
  for (const std::string& w : warnings)
    std::fprintf(stderr, "plastivox export: warning: %s\n", w.c_str());
}

// Writes robot with physics as voxcraft-sim's pair in directory out, printing what was
// dropped (--lossy), what voxcraft-sim does its own way, and the palette's largest error.
void write_voxcraft(const std::string& out, const RobotDef& robot, const PhysicsDef& physics,
                    bool lossy) {
  const VoxcraftFiles f = write_voxcraft_files(out, robot, physics, lossy);
  for (const std::string& w : f.dropped)
    std::fprintf(stderr, "plastivox export: warning: %s\n", w.c_str());
  for (const std::string& w : f.unchanged)
    std::fprintf(stderr, "plastivox export: note: %s\n", w.c_str());
  std::printf("wrote %s/base.vxa and %s/robot.vxd: %d materials, largest stiffness error %.3g %%\n",
              out.c_str(), out.c_str(), f.materials, 100 * f.max_stiffness_error);
}

}  // namespace

int cmd_export(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const std::string gen_text = take_option(args, "--generation", "");
  const std::string demo = take_option(args, "--demo", "");
  const std::string format = take_option(args, "--format", "");
  const bool lossy = take_flag(args, "--lossy");
  reject_unknown_options(args);
  const bool voxcraft = format == "voxcraft";
  if (!format.empty() && !voxcraft)
    throw UsageError{"--format expects voxcraft (other formats follow --out's extension), got '" +
                     format + "'"};
  if (lossy && !voxcraft) throw UsageError{"--lossy applies to --format voxcraft only"};
  if (out.empty())
    throw UsageError{voxcraft ? "--out DIR is required (base.vxa and robot.vxd go there)"
                              : "--out ROBOT.vxa (or ROBOT.json) is required"};
  if (!voxcraft && !out.ends_with(".vxa") && !out.ends_with(".json"))
    throw UsageError{"--out must end in .vxa or .json, got '" + out + "'"};
  // The robot: a demo (with the physics `plastivox simulate` gives the built-in walker:
  // gecco2018-code, stress development), a robot file, or a run's champion.
  if (!demo.empty() || (args.size() == 1 && !args[0].ends_with(".h5"))) {
    if (!demo.empty() && !args.empty()) throw UsageError{"--demo NAME takes no results file"};
    if (!gen_text.empty()) throw UsageError{"--generation applies to a results file (.h5)"};
    RobotDef robot;
    PhysicsDef physics = preset_gecco2018_code();
    if (!demo.empty()) {
      robot = demo_example(demo);
      physics.treatment = Treatment::kStress;
    } else {
      LoadedRobot file = load_robot(args[0]);
      for (const std::string& w : file.warnings)
        std::fprintf(stderr, "plastivox export: warning: %s\n", w.c_str());
      robot = std::move(file.robot);
      physics = file.physics;
    }
    if (voxcraft)
      write_voxcraft(out, robot, physics, lossy);
    else
      write_robot(out, robot, physics);
    if (!demo.empty())
      std::printf("wrote %s: example robot %s (%d voxels)\n", out.c_str(), demo.c_str(),
                  robot.voxel_count());
    return 0;
  }
  if (args.size() != 1)
    throw UsageError{
        "expected one results file or robot file: plastivox export RESULTS.h5 --out "
        "ROBOT.vxa"};

  const evo::ResultsFile results = evo::read_results(args[0]);
  const evo::RunState& run = results.state;
  int generation = -1;
  if (!gen_text.empty()) {
    size_t used = 0;
    try {
      generation = std::stoi(gen_text, &used);
    } catch (...) {
      used = 0;
    }
    if (used != gen_text.size() || generation < 0)
      throw UsageError{"--generation expects a generation number, got '" + gen_text + "'"};
  }
  const evo::ChampionRecord& champion = evo::champion_at(run, generation, args[0]);
  if (generation < 0) generation = run.generations_done;
  const RobotDef robot = evo::champion_robot(champion, generation);
  const PhysicsDef& physics = run.config.physics;
  if (voxcraft)
    write_voxcraft(out, robot, physics, lossy);
  else
    write_robot(out, robot, physics);
  std::printf("wrote %s: champion %llu (fitness %.6g, %d voxels) at generation %d\n", out.c_str(),
              static_cast<unsigned long long>(champion.id), champion.fitness, robot.voxel_count(),
              generation);
  return 0;
}

}  // namespace plastivox::cli
