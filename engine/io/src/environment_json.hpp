// The "environment" object of a physics section (docs/environments.md): read with errors
// naming the file and field, and written back so that a robot file round-trips it.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/environment.hpp"

namespace plastivox {

// Reads j (at `field`, e.g. "physics.environment") into an Environment; InputError
// "<source>: <field>.<key>: ..." for a wrong type, an unknown key, a ragged or oversized
// array. validate(const Environment&) then checks the values.
Environment parse_environment(const nlohmann::json& j, const std::string& source,
                              const std::string& field);

// The object parse_environment reads back into the same Environment (only the fields of
// the ground's kind).
nlohmann::json environment_to_json(const Environment& env);

}  // namespace plastivox
