// Parsing a JSON input file (robot, config, physics overrides) strictly: nlohmann's parser
// keeps the last of two equal keys in one object silently; here a key given twice is an
// error naming it, like every other mistake in an input (docs/robot-format.md).
// Include only where nlohmann_json is linked.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace plastivox {

// Throws InputError: "<source>: <field>: not valid JSON: ..." for a syntax error (field is
// "(file)" for a whole file), "<source>: <a.b.key>: given twice" for a duplicate key.
nlohmann::json parse_json_input(std::string_view text, const std::string& source,
                                const std::string& field = "(file)");

}  // namespace plastivox
