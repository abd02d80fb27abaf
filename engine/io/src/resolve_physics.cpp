#include "plastivox/io/resolve_physics.hpp"

#include "physics_object.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/json_input.hpp"

namespace plastivox {

PhysicsDef with_preset(const PhysicsDef& d, const std::string& name) {
  PhysicsDef out = physics_preset(name);
  out.treatment = d.treatment;
  out.task = d.task;
  out.task_params = d.task_params;
  return out;
}

PhysicsDef resolve_physics(const PhysicsDef& robot, const PhysicsRequest& req) {
  PhysicsDef d = robot;
  if (req.whole) {
    d = *req.whole;
    d.treatment = robot.treatment;
    d.task = robot.task;
    d.task_params = robot.task_params;
  } else if (!req.preset.empty()) {
    try {
      d = with_preset(d, req.preset);
    } catch (const std::invalid_argument& e) {
      json_field::fail(req.where, "physics.preset", e.what());
    }
  }
  if (!req.fields.empty())
    apply_physics_object(parse_json_input(req.fields, req.where, "physics"), req.where, d);
  if (req.treatment) d.treatment = *req.treatment;
  if (req.task) {
    if (*req.task != d.task) d.task_params.clear();  // they were the other task's
    d.task = *req.task;
  }
  if (req.task_params) d.task_params = *req.task_params;
  if (req.duration) d.duration = *req.duration;
  try {
    validate(d);
  } catch (const std::invalid_argument& e) {
    throw InputError(req.where + ": " + e.what());
  }
  return d;
}

}  // namespace plastivox
