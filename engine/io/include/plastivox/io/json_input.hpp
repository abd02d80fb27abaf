// Parsing a JSON input file (robot, config, physics overrides) strictly: nlohmann's parser
// keeps the last of two equal keys in one object silently; here a key given twice is an
// error naming it, like every other mistake in an input (docs/robot-format.md).
// Include only where nlohmann_json is linked.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "plastivox/controller_def.hpp"
#include "plastivox/physics_def.hpp"

namespace plastivox {

// Objects and arrays nest at most this deep: plastivox's formats need 4 levels, and each
// open level costs memory for its path, so a hostile file of nested brackets is refused as
// it is read rather than after gigabytes.
constexpr int kMaxJsonDepth = 32;

// Throws InputError: "<source>: <field>: not valid JSON: ..." for a syntax error (field is
// "(file)" for a whole file), "<source>: <a.b.key>: given twice" for a duplicate key,
// "<source>: <field>: nested deeper than 32 levels" and "<source>: <field>: a NUL byte at
// offset N" (nlohmann's parser would stop there and ignore whatever follows), and
// "<source>: <field>: an HDF5 file (a plastivox evolution results file), not JSON" for text
// that starts as an HDF5 file does (seal::describe_hdf5).
nlohmann::json parse_json_input(std::string_view text, const std::string& source,
                                const std::string& field = "(file)");

// A whole input file: parse_json_input, then an object whose "format" is `format`. Throws
// InputError "<source>: (file): expected a JSON object" or "<source>: format: expected
// \"<format>\"".
nlohmann::json parse_json_file(std::string_view text, const std::string& source,
                               const std::string& format);

// The first field where two JSON values differ, named by its path with both values:
// "<path>: <a> <a_where>, <b> <b_where>", e.g. ("in the file", "now") gives
// "evolution.seed: 5 in the file, 6 now"; a field missing on one side reads "absent". "" when
// equal. Object keys are visited in sorted order (both sides' keys together), array elements
// by index ("seeds[2]") when the arrays have one length, so the answer never depends on the
// order fields were written in. `path` prefixes every path; the whole value is "(top level)".
std::string first_difference(const nlohmann::json& a, const nlohmann::json& b,
                             const std::string& a_where, const std::string& b_where,
                             const std::string& path = "");

// Reading one field of a parsed input: each throws InputError "<source>: <field>: <what>"
// when the value has the wrong type or range, so every input names its mistakes alike.
namespace json_field {
[[noreturn]] void fail(const std::string& source, const std::string& field,
                       const std::string& what);
double number(const nlohmann::json& j, const std::string& source, const std::string& field);
int integer(const nlohmann::json& j, const std::string& source, const std::string& field);
int integer(const nlohmann::json& j, const std::string& source, const std::string& field, int lo,
            int hi);
std::string text(const nlohmann::json& j, const std::string& source, const std::string& field);
bool boolean(const nlohmann::json& j, const std::string& source, const std::string& field);
// A treatment: "stress" or {"stimulus": "stress", "law": "rate"} ("law" optional).
TreatmentSpec treatment(const nlohmann::json& j, const std::string& source,
                        const std::string& field);
// A task (plastivox/task.hpp): {"name": "climb", "rise": 1, ...} (its parameters, each
// checked against the task's table), or its name alone, "climb" (every parameter at its
// default).
struct TaskSpec {
  Task task = Task::kWalk;
  TaskParams params;
};
TaskSpec task(const nlohmann::json& j, const std::string& source, const std::string& field);
// The JSON of a task: its name alone when no parameter is given, else {"name", parameters}.
nlohmann::json task_json(Task task, const TaskParams& params);
// A controller (docs/control.md): {"kind": ..., "hidden": ..., "every": ..., "weights": [...]};
// "weights" only when with_weights (a robot file), and then exactly as many as the kind and
// hidden size take. Absent fields keep ControllerDef's defaults.
ControllerDef controller(const nlohmann::json& j, const std::string& source,
                         const std::string& field, bool with_weights);
// The same as JSON (hidden and weights only for the neural kinds), exact: parsing it gives d.
nlohmann::json controller_json(const ControllerDef& d);
}  // namespace json_field

}  // namespace plastivox
