#include "environment_json.hpp"

#include <algorithm>
#include <initializer_list>
#include <stdexcept>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/json_input.hpp"

namespace plastivox {
namespace {

using json_field::fail;
using json_field::integer;
using json_field::number;
using json_field::text;
using nlohmann::json;

// Every key of o must be one of `known`.
void only(const json& o, std::initializer_list<const char*> known, const std::string& source,
          const std::string& field) {
  for (auto it = o.begin(); it != o.end(); ++it)
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }))
      fail(source, field + "." + it.key(), "unknown field");
}

// An array of exactly n numbers.
template <size_t N>
std::array<double, N> numbers(const json& j, const std::string& source, const std::string& field) {
  if (!j.is_array() || j.size() != N)
    fail(source, field, "expected an array of " + std::to_string(N) + " numbers");
  std::array<double, N> out;
  for (size_t k = 0; k < N; ++k)
    out[k] = number(j[k], source, field + "[" + std::to_string(k) + "]");
  return out;
}

GroundDef parse_ground(const json& g, const std::string& source, const std::string& field) {
  if (!g.is_object()) fail(source, field, "expected an object with a \"type\"");
  if (!g.contains("type")) fail(source, field + ".type", "missing (" + ground_kind_names() + ")");
  GroundDef d;
  try {
    d.kind = parse_ground_kind(text(g["type"], source, field + ".type"));
  } catch (const std::invalid_argument& e) {
    fail(source, field + ".type", e.what());
  }
  const auto need = [&](const char* key) -> const json& {
    if (!g.contains(key)) fail(source, field + "." + key, "missing");
    return g[key];
  };
  const auto num = [&](const char* key) { return number(need(key), source, field + "." + key); };
  const auto opt = [&](const char* key, double& v) {
    if (g.contains(key)) v = number(g[key], source, field + "." + key);
  };
  const auto profile = [&] {  // the keys every profile along +x may give
    opt("at", d.at);
    opt("edge", d.edge);
  };
  switch (d.kind) {
    case GroundKind::kFlat:
      only(g, {"type", "height"}, source, field);
      opt("height", d.height);
      break;
    case GroundKind::kHeights: {
      only(g, {"type", "cell", "origin", "heights"}, source, field);
      d.cell = num("cell");
      if (g.contains("origin")) d.origin = numbers<2>(g["origin"], source, field + ".origin");
      const json& rows = need("heights");
      const std::string hf = field + ".heights";
      if (!rows.is_array() || rows.empty() || !rows[0].is_array() || rows[0].empty())
        fail(source, hf, "expected rows of heights along x, one row per y: [[h, ...], ...]");
      d.ny = static_cast<int>(std::min<size_t>(rows.size(), kMaxGroundNodes + 1));
      d.nx = static_cast<int>(std::min<size_t>(rows[0].size(), kMaxGroundNodes + 1));
      if (int64_t{d.nx} * d.ny > kMaxGroundNodes)
        fail(source, hf, "more than " + std::to_string(kMaxGroundNodes) + " heights");
      d.heights.reserve(static_cast<size_t>(d.nx) * d.ny);
      for (int j = 0; j < d.ny; ++j) {
        const std::string row = hf + "[" + std::to_string(j) + "]";
        if (!rows[j].is_array() || rows[j].size() != static_cast<size_t>(d.nx))
          fail(source, row,
               "expected " + std::to_string(d.nx) + " heights, as row 0 (rows must not be ragged)");
        for (int i = 0; i < d.nx; ++i)
          d.heights.push_back(number(rows[j][i], source, row + "[" + std::to_string(i) + "]"));
      }
      break;
    }
    case GroundKind::kRamp:
      only(g, {"type", "angle_deg", "length", "at", "edge"}, source, field);
      d.angle_deg = num("angle_deg");
      d.length = num("length");
      profile();
      break;
    case GroundKind::kStep:
      only(g, {"type", "height", "at", "edge"}, source, field);
      d.height = num("height");
      profile();
      break;
    case GroundKind::kStairs:
      only(g, {"type", "rise", "run", "count", "at", "edge"}, source, field);
      d.rise = num("rise");
      d.run = num("run");
      d.count = integer(need("count"), source, field + ".count", 1, 100000);
      profile();
      break;
    case GroundKind::kGap:
      only(g, {"type", "width", "depth", "at", "edge"}, source, field);
      d.width = num("width");
      d.depth = num("depth");
      profile();
      break;
    case GroundKind::kRough: {
      only(g, {"type", "amplitude", "cell", "nodes", "origin", "seed"}, source, field);
      d.amplitude = num("amplitude");
      d.cell = num("cell");
      const json& nodes = need("nodes");
      if (!nodes.is_array() || nodes.size() != 2)
        fail(source, field + ".nodes", "expected [nx, ny], nodes along x and y");
      d.nx = integer(nodes[0], source, field + ".nodes[0]", 1, 1 << 22);
      d.ny = integer(nodes[1], source, field + ".nodes[1]", 1, 1 << 22);
      if (g.contains("origin")) d.origin = numbers<2>(g["origin"], source, field + ".origin");
      if (g.contains("seed")) {
        if (!g["seed"].is_number_unsigned())
          fail(source, field + ".seed", "expected a non-negative integer");
        d.seed = g["seed"].get<uint64_t>();
      }
      break;
    }
    case GroundKind::kNone:
      break;
  }
  return d;
}

// "objects": [{"voxels": [nx, ny, nz], "at": [x, y, z], "stiffness": E}, ...]; the
// ranges are checked by validate(Environment).
std::vector<ObjectDef> parse_objects(const json& list, const std::string& source,
                                     const std::string& of) {
  const char* shape = "expected an array of {\"voxels\": [nx, ny, nz], \"at\": [x, y, z]}";
  if (!list.is_array()) fail(source, of, shape);
  if (list.size() > static_cast<size_t>(kMaxObjects))
    fail(source, of, "more than " + std::to_string(kMaxObjects) + " objects");
  std::vector<ObjectDef> objects;
  for (size_t b = 0; b < list.size(); ++b) {
    const std::string bf = of + "[" + std::to_string(b) + "]";
    const json& o = list[b];
    if (!o.is_object()) fail(source, bf, shape);
    only(o, {"voxels", "at", "stiffness"}, source, bf);
    if (!o.contains("voxels")) fail(source, bf + ".voxels", "missing (the extent [nx, ny, nz])");
    if (!o.contains("at")) fail(source, bf + ".at", "missing (the lowest corner [x, y, z], m)");
    ObjectDef d;
    const json& v = o["voxels"];
    if (!v.is_array() || v.size() != 3)
      fail(source, bf + ".voxels", "expected [nx, ny, nz], whole voxels along x, y and z");
    for (int a = 0; a < 3; ++a)
      d.voxels[a] = integer(v[a], source, bf + ".voxels[" + std::to_string(a) + "]", 1, 1000);
    d.at = numbers<3>(o["at"], source, bf + ".at");
    if (o.contains("stiffness")) d.stiffness = number(o["stiffness"], source, bf + ".stiffness");
    objects.push_back(d);
  }
  return objects;
}

}  // namespace

Environment parse_environment(const json& j, const std::string& source, const std::string& field) {
  if (!j.is_object())
    fail(source, field, "expected an object with \"ground\", \"obstacles\" and/or \"objects\"");
  only(j, {"ground", "obstacles", "objects"}, source, field);
  Environment env;
  if (j.contains("ground")) env.ground = parse_ground(j["ground"], source, field + ".ground");
  if (j.contains("obstacles")) {
    const json& list = j["obstacles"];
    const std::string of = field + ".obstacles";
    if (!list.is_array())
      fail(source, of, "expected an array of {\"min\": [x, y, z], \"max\": [x, y, z]}");
    if (list.size() > static_cast<size_t>(kMaxObstacles))
      fail(source, of, "more than " + std::to_string(kMaxObstacles) + " boxes");
    for (size_t b = 0; b < list.size(); ++b) {
      const std::string bf = of + "[" + std::to_string(b) + "]";
      const json& o = list[b];
      if (!o.is_object() || !o.contains("min") || !o.contains("max"))
        fail(source, bf, "expected {\"min\": [x, y, z], \"max\": [x, y, z]}");
      only(o, {"min", "max"}, source, bf);
      ObstacleBox box;
      box.min = numbers<3>(o["min"], source, bf + ".min");
      box.max = numbers<3>(o["max"], source, bf + ".max");
      env.obstacles.push_back(box);
    }
  }
  if (j.contains("objects")) env.objects = parse_objects(j["objects"], source, field + ".objects");
  try {
    validate(env);
  } catch (const std::invalid_argument& e) {
    throw InputError(source + ": " + e.what());
  }
  return env;
}

json environment_to_json(const Environment& env) {
  json out = json::object();
  const GroundDef& d = env.ground;
  if (d.kind != GroundKind::kNone) {
    json g = {{"type", to_string(d.kind)}};
    const auto profile = [&] {
      g["at"] = d.at;
      g["edge"] = d.edge;
    };
    switch (d.kind) {
      case GroundKind::kFlat:
        g["height"] = d.height;
        break;
      case GroundKind::kHeights: {
        g["cell"] = d.cell;
        g["origin"] = d.origin;
        json rows = json::array();
        for (int j = 0; j < d.ny; ++j)
          rows.push_back(std::vector<double>(d.heights.begin() + size_t(d.nx) * j,
                                             d.heights.begin() + size_t(d.nx) * (j + 1)));
        g["heights"] = rows;
        break;
      }
      case GroundKind::kRamp:
        g["angle_deg"] = d.angle_deg;
        g["length"] = d.length;
        profile();
        break;
      case GroundKind::kStep:
        g["height"] = d.height;
        profile();
        break;
      case GroundKind::kStairs:
        g["rise"] = d.rise;
        g["run"] = d.run;
        g["count"] = d.count;
        profile();
        break;
      case GroundKind::kGap:
        g["width"] = d.width;
        g["depth"] = d.depth;
        profile();
        break;
      case GroundKind::kRough:
        g["amplitude"] = d.amplitude;
        g["cell"] = d.cell;
        g["nodes"] = {d.nx, d.ny};
        g["origin"] = d.origin;
        g["seed"] = d.seed;
        break;
      case GroundKind::kNone:
        break;
    }
    out["ground"] = g;
  }
  if (!env.obstacles.empty()) {
    json list = json::array();
    for (const ObstacleBox& b : env.obstacles) list.push_back({{"min", b.min}, {"max", b.max}});
    out["obstacles"] = list;
  }
  if (!env.objects.empty()) {
    json list = json::array();
    for (const ObjectDef& o : env.objects) {
      json e = {{"voxels", o.voxels}, {"at", o.at}};
      if (o.stiffness != 0) e["stiffness"] = o.stiffness;
      list.push_back(e);
    }
    out["objects"] = list;
  }
  return out;
}

}  // namespace plastivox
