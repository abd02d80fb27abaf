// The robot file's reader of a "physics" object, for resolve_physics (private to io).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/physics_def.hpp"

namespace plastivox {

// Applies the fields of JSON object `p` to d ("preset" first: resolve_physics.hpp's with_preset)
// without validating the whole. Throws InputError "<where>: physics.<field>: ...".
void apply_physics_object(const nlohmann::json& p, const std::string& where, PhysicsDef& d);

}  // namespace plastivox
