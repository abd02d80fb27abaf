// One way to resolve the physics of a life from what a run names beside its robot: the
// command line (simulate's --preset, --physics, --treatment, --task, --duration), Python
// (physics= as a dict or a PhysicsDef, treatment=, task=) and evolution configs ("physics",
// "treatment", "task") all call resolve_physics. The rule is docs/robot-format.md, "Resolving
// a run's physics".
#pragma once

#include <optional>
#include <string>

#include "plastivox/physics_def.hpp"

namespace plastivox {

// What a run names beside its robot; every part is optional.
struct PhysicsRequest {
  // A whole physics in place of the robot's: a preset by name, or `whole` (Python's
  // PhysicsDef), which wins when both are given.
  std::string preset;
  std::optional<PhysicsDef> whole;
  // A JSON object of physics fields applied on top ("" for none), as a robot file's "physics"
  // section reads them; a "preset" among them is applied first, as `preset` is.
  std::string fields;
  std::string where = "physics";  // names the request in errors ("--physics", a config's path)
  // The single fields, which win over everything else.
  std::optional<Treatment> treatment;
  std::optional<Task> task;
  std::optional<TaskParams> task_params;  // with `task`: its parameters
  std::optional<double> duration;         // s
};

// d with the preset `name`'s every field but d's treatment and task (with its parameters): a
// preset is physics, the treatment and task are the experiment. Throws std::invalid_argument
// for an unknown name.
PhysicsDef with_preset(const PhysicsDef& d, const std::string& name);

// The physics of a life, in one order, each step over the last:
//   1. `robot`: the robot file's own physics (an evolution config's: the gecco2018-code
//      preset);
//   2. req.whole, else req.preset, for the treatment and task so far (with_preset);
//   3. req.fields ("preset" first, as in 2; then each field it names);
//   4. the single fields: treatment, task, duration. A task other than the one so far starts
//      from its default parameters unless task_params are given; the same task keeps them.
// Validated once, at the end. Throws InputError "<req.where>: physics.<field>: <what>".
PhysicsDef resolve_physics(const PhysicsDef& robot, const PhysicsRequest& req);

}  // namespace plastivox
