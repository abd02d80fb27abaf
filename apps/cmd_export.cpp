// plastivox export: a champion from an evolution results file (or, with --demo NAME, a
// built-in example robot) as a robot file, in the VXA dialect of the authors' simulator
// (.vxa) or the project's own format (.json).
#include <cstdio>
#include <string>

#include "cli.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/robot_io.hpp"

namespace plastivox::cli {
namespace {

// Writes robot with physics as .vxa (printing the writer's warnings) or .json.
void write_robot(const std::string& out, const RobotDef& robot, const PhysicsDef& physics) {
  std::vector<std::string> warnings;
  save_robot(out, robot, physics, &warnings);
  for (const std::string& w : warnings)
    std::fprintf(stderr, "plastivox export: warning: %s\n", w.c_str());
}

// export --demo NAME: a built-in example robot (demo_example) with the physics `plastivox
// simulate` gives the built-in walker (gecco2018-code, stress development).
int export_demo(const std::string& name, const std::string& out, const Args& rest) {
  if (!rest.empty()) throw UsageError{"--demo NAME takes no results file"};
  if (out.empty()) throw UsageError{"--out ROBOT.vxa (or ROBOT.json) is required"};
  if (!out.ends_with(".vxa") && !out.ends_with(".json"))
    throw UsageError{"--out must end in .vxa or .json, got '" + out + "'"};
  const RobotDef robot = demo_example(name);
  PhysicsDef physics = preset_gecco2018_code();
  physics.treatment = Treatment::kStress;
  write_robot(out, robot, physics);
  std::printf("wrote %s: example robot %s (%d voxels)\n", out.c_str(), name.c_str(),
              robot.voxel_count());
  return 0;
}

}  // namespace

int cmd_export(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const std::string gen_text = take_option(args, "--generation", "");
  const std::string demo = take_option(args, "--demo", "");
  reject_unknown_options(args);
  if (!demo.empty()) return export_demo(demo, out, args);
  if (args.size() != 1)
    throw UsageError{"expected one results file: plastivox export RESULTS.h5 --out ROBOT.vxa"};
  if (out.empty()) throw UsageError{"--out ROBOT.vxa (or ROBOT.json) is required"};
  if (!out.ends_with(".vxa") && !out.ends_with(".json"))
    throw UsageError{"--out must end in .vxa or .json, got '" + out + "'"};

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
  write_robot(out, robot, physics);
  std::printf("wrote %s: champion %llu (fitness %.6g, %d voxels) at generation %d\n", out.c_str(),
              static_cast<unsigned long long>(champion.id), champion.fitness, robot.voxel_count(),
              generation);
  return 0;
}

}  // namespace plastivox::cli
