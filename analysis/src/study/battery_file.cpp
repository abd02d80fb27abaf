// Battery files (docs/analysis.md, "Robustness battery"): JSON read and written here, in
// plastivox_study, so that plastivox_analysis knows no file format.
//
//   {"format": "plastivox-battery", "version": 1,
//    "perturbations": [{"name": "damage", "kind": "voxel-loss",
//                       "severities": [0.02, 0.05, 0.1], "seeds": [0, 1, 2]}, ...]}
//
// "name" is optional (the kind's name). Every error names the file and the field, in one line.
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "plastivox/analysis/battery.hpp"

namespace plastivox::analysis {
namespace {

using Json = nlohmann::ordered_json;

[[noreturn]] void fail(const std::string& where, const std::string& field, const std::string& why) {
  throw std::invalid_argument(where + ": " + field + ": " + why);
}

Perturbation read_perturbation(const Json& j, const std::string& where, const std::string& at) {
  if (!j.is_object()) fail(where, at, "expected an object");
  for (const auto& [key, value] : j.items())
    if (key != "name" && key != "kind" && key != "severities" && key != "seeds")
      fail(where, at + "." + key, "unknown field (expected name, kind, severities, seeds)");
  Perturbation p;
  if (!j.contains("kind")) fail(where, at + ".kind", "missing");
  if (!j.at("kind").is_string()) fail(where, at + ".kind", "expected a name");
  try {
    p.kind = parse_perturbation_kind(j.at("kind").get<std::string>());
  } catch (const std::invalid_argument& e) {
    fail(where, at + ".kind", e.what());
  }
  p.name = to_string(p.kind);
  if (j.contains("name")) {
    if (!j.at("name").is_string()) fail(where, at + ".name", "expected text");
    p.name = j.at("name").get<std::string>();
  }
  if (!j.contains("severities")) fail(where, at + ".severities", "missing");
  if (!j.at("severities").is_array()) fail(where, at + ".severities", "expected an array");
  for (size_t k = 0; k < j.at("severities").size(); ++k) {
    const Json& s = j.at("severities")[k];
    if (!s.is_number())
      fail(where, at + ".severities[" + std::to_string(k) + "]", "expected a number");
    p.severities.push_back(s.get<double>());
  }
  if (!j.contains("seeds")) fail(where, at + ".seeds", "missing");
  if (!j.at("seeds").is_array()) fail(where, at + ".seeds", "expected an array");
  for (size_t k = 0; k < j.at("seeds").size(); ++k) {
    const Json& s = j.at("seeds")[k];
    if (!s.is_number_unsigned())
      fail(where, at + ".seeds[" + std::to_string(k) + "]", "expected a whole number >= 0");
    p.seeds.push_back(s.get<uint64_t>());
  }
  return p;
}

}  // namespace

Battery load_battery(const std::string& spec, int paper_draws) {
  if (spec == "default" || spec == "paper" || spec == "small")
    return builtin_battery(spec, paper_draws);
  std::ifstream in(spec, std::ios::binary);
  if (!in)
    throw std::invalid_argument(spec +
                                ": cannot read the battery (not a file, and not one of the "
                                "built-in batteries default, paper, small)");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_battery(ss.str(), spec);
}

Battery parse_battery(const std::string& text, const std::string& spec) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const std::exception& e) {
    throw std::invalid_argument(spec + ": not JSON: " + e.what());
  }
  if (!j.is_object()) fail(spec, "(top)", "expected an object");
  for (const auto& [key, value] : j.items())
    if (key != "format" && key != "version" && key != "perturbations")
      fail(spec, key, "unknown field (expected format, version, perturbations)");
  if (!j.contains("format") || j.at("format") != "plastivox-battery")
    fail(spec, "format", "expected \"plastivox-battery\"");
  if (!j.contains("version") || j.at("version") != 1) fail(spec, "version", "expected 1");
  if (!j.contains("perturbations") || !j.at("perturbations").is_array())
    fail(spec, "perturbations", "expected an array");
  Battery b;
  b.name = spec;
  for (size_t i = 0; i < j.at("perturbations").size(); ++i)
    b.perturbations.push_back(read_perturbation(j.at("perturbations")[i], spec,
                                                "perturbations[" + std::to_string(i) + "]"));
  validate(b, spec);
  return b;
}

std::string battery_json(const Battery& b) {
  Json ps = Json::array();
  for (const Perturbation& p : b.perturbations)
    ps.push_back({{"name", p.name},
                  {"kind", to_string(p.kind)},
                  {"severities", p.severities},
                  {"seeds", p.seeds}});
  const Json j = {{"format", "plastivox-battery"}, {"version", 1}, {"perturbations", ps}};
  return j.dump(1) + "\n";
}

}  // namespace plastivox::analysis
