#include "plastivox/io/robot_file.hpp"

#include <algorithm>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "environment_json.hpp"
#include "physics_object.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/resolve_physics.hpp"

namespace plastivox {
namespace {

using nlohmann::json;

using json_field::boolean;
using json_field::fail;
using json_field::integer;
using json_field::number;
using json_field::text;

int site_of(const RobotDef& r, const json& xyz, const std::string& source,
            const std::string& field) {
  if (!xyz.is_array() || xyz.size() != 3) fail(source, field, "expected [x, y, z]");
  const int x = integer(xyz[0], source, field + "[0]");
  const int y = integer(xyz[1], source, field + "[1]");
  const int z = integer(xyz[2], source, field + "[2]");
  if (x < 0 || y < 0 || z < 0 || x >= r.nx || y >= r.ny || z >= r.nz)
    fail(source, field, "lattice coordinate outside the lattice");
  return r.site(x, y, z);
}

}  // namespace

void apply_physics_object(const json& p, const std::string& where, PhysicsDef& d) {
  if (!p.is_object()) fail(where, "physics", "expected an object");
  if (p.contains("preset")) {  // for the treatment and task so far (resolve_physics.hpp)
    try {
      d = with_preset(d, text(p["preset"], where, "physics.preset"));
    } catch (const std::invalid_argument& e) {
      fail(where, "physics.preset", e.what());
    }
  }
  for (auto it = p.begin(); it != p.end(); ++it) {
    const std::string key = it.key(), field = "physics." + key;
    if (key == "preset") continue;
    try {
      if (key == "record_fps") {
        // Files written while recording was a physics field carry it: checked, and otherwise
        // unused (a recording is asked for by the command: simulate --record, --fps).
        const double fps = number(*it, where, field);
        if (!(fps >= 0 && fps <= 10000)) fail(where, field, "must be in [0, 10000]");
        continue;
      }
      if (key == "environment") {  // ground and obstacles (docs/environments.md)
        d.environment = parse_environment(*it, where, field);
        continue;
      }
      if (key == "task") {  // a name, or {name, parameters} (docs/tasks.md)
        const json_field::TaskSpec t = json_field::task(*it, where, field);
        d.task = t.task;
        d.task_params = t.params;
        continue;
      }
      if (key == "treatment") {  // a name, or {stimulus, law}
        const TreatmentSpec t = json_field::treatment(*it, where, field);
        d.treatment = t.stimulus;
        if (t.law) {
          if (p.contains("growth") &&
              parse_growth(text(p["growth"], where, "physics.growth")) != *t.law)
            fail(where, field + ".law", "contradicts physics.growth (give the law once)");
          d.growth = *t.law;
        }
        continue;
      }
      const auto f = std::find_if(kPhysicsFields.begin(), kPhysicsFields.end(),
                                  [&](const PhysicsField& f) { return key == f.name; });
      if (f == kPhysicsFields.end()) fail(where, field, "unknown field");
      switch (f->kind) {
        case PhysicsField::Kind::kNumber:
          d.*f->number = number(*it, where, field);
          break;
        case PhysicsField::Kind::kFlag:
          d.*f->flag = boolean(*it, where, field);
          break;
        case PhysicsField::Kind::kWhole:
          d.*f->whole = integer(*it, where, field);
          break;
        case PhysicsField::Kind::kChoice:
          f->set(d, text(*it, where, field));
          break;
      }
    } catch (const std::invalid_argument& e) {
      fail(where, field, e.what());
    }
  }
}

namespace {

void apply_physics(const json& p, const std::string& where, PhysicsDef& d) {
  apply_physics_object(p, where, d);
  try {
    validate(d);
  } catch (const std::invalid_argument& e) {
    throw InputError(where + ": " + e.what());
  }
}

// The physics section: every field of kPhysicsFields, and the environment when defined.
json physics_json(const PhysicsDef& d) {
  const PhysicsDef defaults;
  json out = json::object();
  for (const PhysicsField& f : kPhysicsFields) {
    switch (f.kind) {
      case PhysicsField::Kind::kNumber:
        if (!f.written_when_not_default || d.*f.number != defaults.*f.number)
          out[f.name] = d.*f.number;
        break;
      case PhysicsField::Kind::kFlag:
        if (!f.written_when_not_default || d.*f.flag != defaults.*f.flag) out[f.name] = d.*f.flag;
        break;
      case PhysicsField::Kind::kWhole:
        out[f.name] = d.*f.whole;
        break;
      case PhysicsField::Kind::kChoice:
        if (!f.written_when_not_default || std::strcmp(f.get(d), f.get(defaults)) != 0)
          out[f.name] = f.get(d);
        break;
    }
  }
  if (!d.task_params.empty()) out["task"] = json_field::task_json(d.task, d.task_params);
  // Only when defined, so files (and evolution identities) of the plain floor keep their
  // bytes.
  if (d.environment.active()) out["environment"] = environment_to_json(d.environment);
  return out;
}

}  // namespace

std::string physics_to_json(const PhysicsDef& def) {
  return physics_json(def).dump();
}

void apply_physics_json(const std::string& json_text, const std::string& where, PhysicsDef& def) {
  apply_physics(parse_json_input(json_text, where, "physics"), where, def);
}

RobotFile parse_robot_json(const std::string& src, const std::string& source) {
  json j = parse_json_file(src, source, "plastivox-robot");
  if (!j.contains("version")) fail(source, "version", "missing");
  const int version = integer(j["version"], source, "version");
  if (version != 1)
    fail(source, "version",
         "unsupported version " + std::to_string(version) + " (this build reads 1)");
  // Every key of object `o` must be one of `known`; `prefix` names where o sits.
  const auto only = [&](const json& o, std::initializer_list<const char*> known,
                        const std::string& prefix) {
    for (auto it = o.begin(); it != o.end(); ++it)
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }))
        fail(source, prefix + it.key(), "unknown field");
  };
  only(j,
       {"format", "version", "name", "lattice", "voxels", "act_scale", "controller", "fixed",
        "loads", "physics"},
       "");
  if (!j.contains("lattice")) fail(source, "lattice", "missing");
  const json& lat = j["lattice"];
  if (!lat.is_object()) fail(source, "lattice", "expected an object");
  only(lat, {"nx", "ny", "nz", "voxel_size"}, "lattice.");
  for (const char* k : {"nx", "ny", "nz", "voxel_size"})
    if (!lat.contains(k)) fail(source, std::string("lattice.") + k, "missing");
  const int nx = integer(lat["nx"], source, "lattice.nx");
  const int ny = integer(lat["ny"], source, "lattice.ny");
  const int nz = integer(lat["nz"], source, "lattice.nz");
  const Limits limits = limits_from_environment();
  try {  // before anything is allocated
    check_lattice_size(nx, ny, nz, limits);
  } catch (const std::invalid_argument& e) {
    fail(source, "lattice", std::string(e.what()).substr(std::strlen("robot.size: ")));
  }
  const double size = number(lat["voxel_size"], source, "lattice.voxel_size");
  if (!(size >= kMinVoxelSize && size <= kMaxVoxelSize))
    fail(source, "lattice.voxel_size", "must be in [1e-4, 10] m");
  RobotFile out;
  RobotDef& r = out.robot;
  r = make_empty_robot(nx, ny, nz, size, limits);
  if (j.contains("name")) r.name = text(j["name"], source, "name");
  if (!j.contains("voxels") || !j["voxels"].is_array())
    fail(source, "voxels", "missing or not an array");
  const json& vox = j["voxels"];
  // A 7th entry is the voxel's own actuation amplitude (RobotDef::act_amplitude): every voxel
  // has one or none does.
  const bool own_amplitude = !vox.empty() && vox[0].is_array() && vox[0].size() == 7;
  if (own_amplitude) r.act_amplitude.assign(r.sites(), 0.0);
  for (size_t k = 0; k < vox.size(); ++k) {
    const std::string field = "voxels[" + std::to_string(k) + "]";
    const json& v = vox[k];
    if (!v.is_array() || v.size() != (own_amplitude ? 7u : 6u))
      fail(source, field,
           own_amplitude ? "expected [x, y, z, E, alpha, phase, amplitude] (as voxels[0])"
                         : "expected [x, y, z, E, alpha, phase]");
    const int s = site_of(r, json::array({v[0], v[1], v[2]}), source, field);
    if (r.present[s]) fail(source, field, "a second voxel at the same site");
    r.present[s] = 1;
    r.stiffness[s] = number(v[3], source, field + "[3] (E)");
    r.dev_rate[s] = number(v[4], source, field + "[4] (alpha)");
    r.phase[s] = number(v[5], source, field + "[5] (phase)");
    if (own_amplitude) r.act_amplitude[s] = number(v[6], source, field + "[6] (amplitude)");
  }
  // Optional: each voxel's actuation scale in [0, 1], one per entry of voxels, in its order.
  if (j.contains("act_scale")) {
    const json& scale = j["act_scale"];
    if (!scale.is_array() || scale.size() != vox.size())
      fail(source, "act_scale",
           "expected an array of " + std::to_string(vox.size()) + " numbers (one per voxel)");
    r.act_scale.assign(r.sites(), 1.0);
    for (size_t k = 0; k < vox.size(); ++k) {
      const std::string field = "act_scale[" + std::to_string(k) + "]";
      const double a = number(scale[k], source, field);
      if (!(a >= 0 && a <= 1)) fail(source, field, "must be in [0, 1] (0: passive tissue)");
      r.act_scale[site_of(r, json::array({vox[k][0], vox[k][1], vox[k][2]}), source,
                          "voxels[" + std::to_string(k) + "]")] = a;
    }
  }
  if (j.contains("controller"))
    r.controller = json_field::controller(j["controller"], source, "controller", true);
  if (j.contains("fixed")) {
    if (!j["fixed"].is_array()) fail(source, "fixed", "expected an array");
    for (size_t k = 0; k < j["fixed"].size(); ++k)
      r.fixed_sites.push_back(
          site_of(r, j["fixed"][k], source, "fixed[" + std::to_string(k) + "]"));
  }
  if (j.contains("loads")) {
    if (!j["loads"].is_array()) fail(source, "loads", "expected an array");
    for (size_t k = 0; k < j["loads"].size(); ++k) {
      const std::string field = "loads[" + std::to_string(k) + "]";
      const json& l = j["loads"][k];
      if (!l.is_object() || !l.contains("at") || !l.contains("force") || !l["force"].is_array() ||
          l["force"].size() != 3)
        fail(source, field, "expected {\"at\": [x, y, z], \"force\": [fx, fy, fz]}");
      only(l, {"at", "force"}, field + ".");
      RobotDef::Load load;
      load.site = site_of(r, l["at"], source, field + ".at");
      load.fx = number(l["force"][0], source, field + ".force[0]");
      load.fy = number(l["force"][1], source, field + ".force[1]");
      load.fz = number(l["force"][2], source, field + ".force[2]");
      r.loads.push_back(load);
    }
  }
  if (j.contains("physics")) apply_physics(j["physics"], source, out.physics);
  try {
    validate(r, limits);
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": " + e.what());
  }
  return out;
}

RobotFile read_robot_file(const std::string& path) {
  return parse_robot_json(read_file_bytes(path), path);
}

std::string robot_to_json(const RobotDef& r, const PhysicsDef* physics) {
  json j;
  j["format"] = "plastivox-robot";
  j["version"] = 1;
  j["name"] = r.name;
  j["lattice"] = {{"nx", r.nx}, {"ny", r.ny}, {"nz", r.nz}, {"voxel_size", r.voxel_size}};
  json vox = json::array();
  for (int s = 0; s < r.sites(); ++s) {
    if (!r.present[s]) continue;
    const int x = s % r.nx, y = (s / r.nx) % r.ny, z = s / (r.nx * r.ny);
    vox.push_back({x, y, z, r.stiffness[s], r.dev_rate[s], r.phase[s]});
    if (!r.act_amplitude.empty()) vox.back().push_back(r.act_amplitude[s]);
  }
  j["voxels"] = vox;
  if (!r.act_scale.empty()) {
    json& scale = j["act_scale"] = json::array();
    for (int s = 0; s < r.sites(); ++s)
      if (r.present[s]) scale.push_back(r.act_scale[s]);
  }
  // Only when not the default sine, so every other robot file keeps its bytes.
  if (!r.controller.is_default()) j["controller"] = json_field::controller_json(r.controller);
  auto xyz = [&](int s) { return json::array({s % r.nx, (s / r.nx) % r.ny, s / (r.nx * r.ny)}); };
  if (!r.fixed_sites.empty()) {
    j["fixed"] = json::array();
    for (int s : r.fixed_sites) j["fixed"].push_back(xyz(s));
  }
  if (!r.loads.empty()) {
    j["loads"] = json::array();
    for (const auto& l : r.loads)
      j["loads"].push_back({{"at", xyz(l.site)}, {"force", {l.fx, l.fy, l.fz}}});
  }
  if (physics) j["physics"] = physics_json(*physics);
  return j.dump(1);
}

void write_robot_file(const std::string& path, const RobotDef& robot, const PhysicsDef* physics) {
  write_file_atomic(path, robot_to_json(robot, physics) + "\n");
}

}  // namespace plastivox
