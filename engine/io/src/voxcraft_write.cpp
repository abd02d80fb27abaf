// Export for voxcraft-sim: base.vxa (settings, environment, lattice) and robot.vxd (palette and
// structure, each replacing its subtree of the base). Which plastivox field becomes which tag,
// and what cannot be written: docs/vxa.md, "voxcraft-sim".
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/voxcraft.hpp"
#include "plastivox/task.hpp"
#include "voxcraft_internal.hpp"
#include "vxa_internal.hpp"

namespace plastivox {
namespace {

using namespace vxa_detail;

// The runs of a greedy cover of sorted `lg` by windows of width `width`: [first, last] each.
std::vector<std::pair<size_t, size_t>> cover(const std::vector<double>& lg, double width) {
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t i = 0, j = 0; i < lg.size(); i = ++j) {
    while (j + 1 < lg.size() && lg[j + 1] - lg[i] <= width) ++j;
    runs.emplace_back(i, j);
  }
  return runs;
}

// One palette entry: a stiffness level and the linear actuation amplitude that goes with it.
struct Material {
  double e = 0, amplitude = 0;
  bool operator<(const Material& o) const { return e != o.e ? e < o.e : amplitude < o.amplitude; }
};

// XML text of an ASCII_READABLE layer: the characters that are markup are escaped.
std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

void write_material(Xml& x, const Material& m, double position, const PhysicsDef& p) {
  x.open("Material");
  x.tag("MatType", 0);
  std::string name = "E";  // (not "E" + ...: GCC 12 warns falsely, -Wrestrict, in unity builds)
  name += format_double(m.e);
  x.tag("Name", name);
  // Colour by stiffness over the palette (soft blue to stiff red), as voxcraft-viz shows it.
  x.open("Display");
  x.tag("Red", position);
  x.tag("Green", 0.2);
  x.tag("Blue", 1.0 - position);
  x.tag("Alpha", 1);
  x.close();
  x.open("Mechanical");
  x.tag("MatModel", 0);
  x.tag("Elastic_Mod", m.e);
  x.tag("Fail_Stress", 0);
  x.tag("Density", p.density);
  x.tag("Poissons_Ratio", p.poisson);
  x.tag("CTE", m.amplitude);  // TempAmplitude is 1: the CTE is the linear amplitude
  x.tag("MaterialTempPhase", 0);
  x.tag("uStatic", p.mu_static);
  x.tag("uDynamic", p.mu_kinetic);
  x.tag("TurnOnThermalExpansionAfterThisManySeconds", p.settle_time);
  x.close();
  x.close();
}

}  // namespace

StiffnessPalette quantise_stiffness(const std::vector<double>& values, int max_levels) {
  if (max_levels < 1) throw std::invalid_argument("quantise_stiffness: max_levels must be >= 1");
  for (double v : values)
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("quantise_stiffness: values must be positive and finite");
  std::vector<double> u = values;
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  std::vector<double> lg(u.size());
  for (size_t i = 0; i < u.size(); ++i) lg[i] = std::log(u[i]);
  // The narrowest window (found by bisection) whose cover needs at most max_levels runs.
  double width = 0;
  if (static_cast<int>(u.size()) > max_levels) {
    double lo = 0, hi = lg.back() - lg.front();
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      (static_cast<int>(cover(lg, mid).size()) <= max_levels ? hi : lo) = mid;
    }
    width = hi;
  }
  StiffnessPalette out;
  std::vector<int> run_of(u.size());
  for (const auto& [first, last] : cover(lg, width)) {
    for (size_t i = first; i <= last; ++i) run_of[i] = static_cast<int>(out.levels.size());
    out.levels.push_back(first == last ? u[first] : std::sqrt(u[first] * u[last]));
  }
  out.level_of.reserve(values.size());
  for (double v : values) {
    const int k = run_of[std::lower_bound(u.begin(), u.end(), v) - u.begin()];
    out.level_of.push_back(k);
    out.max_rel_error = std::max(out.max_rel_error, std::abs(out.levels[k] - v) / v);
  }
  return out;
}

double voxcraft_dt_ratio(const RobotDef& r, const std::vector<double>& e) {
  double top = 0, bond = 0;
  for (int s = 0; s < r.sites(); ++s) {
    if (!r.present[s]) continue;
    top = std::max(top, e[s]);
    const int c[3] = {s % r.nx, (s / r.nx) % r.ny, s / (r.nx * r.ny)};
    const int extent[3] = {r.nx, r.ny, r.nz};
    const int stride[3] = {1, r.nx, r.nx * r.ny};
    for (int axis = 0; axis < 3; ++axis) {
      if (c[axis] + 1 >= extent[axis] || !r.present[s + stride[axis]]) continue;
      const double a = e[s], b = e[s + stride[axis]];
      bond = std::max(bond, 2.0 * a * b / (a + b));
    }
  }
  return bond > 0 && bond < top ? std::sqrt(bond / top) : 1.0;
}

VoxcraftFiles write_voxcraft(const RobotDef& robot, const PhysicsDef& p, bool lossy) {
  validate(robot);
  validate(p);
  VoxcraftFiles out;
  // What voxcraft-sim cannot express: refused, or dropped with a line under lossy.
  auto cannot = [&](const std::string& what) {
    if (!lossy)
      throw VxaError("voxcraft export: " + what +
                     " cannot be expressed in voxcraft-sim's files (--lossy drops it)");
    out.dropped.push_back(what + ": dropped");
  };
  int developing = 0;
  for (int s = 0; s < robot.sites(); ++s)
    developing += robot.present[s] && robot.dev_rate[s] != 0 && p.treatment != Treatment::kNone;
  if (developing > 0)
    cannot(std::string("development (treatment ") + to_string(p.treatment) + ", " +
           std::to_string(developing) + " voxels with nonzero development rates, its stimulus)");
  if (!robot.fixed_sites.empty()) cannot("fixed voxels (robot.fixed_sites)");
  if (!robot.loads.empty()) cannot("external loads (robot.loads)");
  if (!robot.act_scale.empty()) cannot("per-voxel actuation scales (robot.act_scale)");
  if (p.environment.active())
    cannot("the environment (physics.environment: a ground or obstacles beyond the flat floor)");
  if (p.task != Task::kWalk)
    cannot(std::string("the task (physics.task '") + to_string(p.task) +
           "'; voxcraft-sim's fitness here is the walk's displacement)");
  if (!robot.controller.is_default())
    cannot(std::string("a ") + to_string(robot.controller.kind) +
           " controller (robot.controller; voxcraft-sim runs the sine)");

  // Per voxel: congenital stiffness as compile() holds it, and the linear amplitude.
  const bool own = !robot.act_amplitude.empty();
  std::vector<int> sites;
  std::vector<double> e;
  for (int s = 0; s < robot.sites(); ++s)
    if (robot.present[s]) {
      sites.push_back(s);
      e.push_back(std::clamp(robot.stiffness[s], p.e_min, p.e_max));
    }
  const StiffnessPalette pal = quantise_stiffness(e, kVoxcraftMaxMaterials);
  const double inv_range = 1.0 / (p.e_max - p.e_min);
  std::vector<Material> voxel_material(sites.size());
  double amplitude_max = 0;
  for (size_t i = 0; i < sites.size(); ++i) {
    const double level = pal.levels[pal.level_of[i]];
    const double a =
        own ? robot.act_amplitude[sites[i]] : p.act_amplitude * ((p.e_max - level) * inv_range);
    voxel_material[i] = {level, p.act_frequency > 0 ? a : 0.0};
    amplitude_max = std::max(amplitude_max, voxel_material[i].amplitude);
  }
  if (amplitude_max > 0 && 1.0 - amplitude_max < p.act_min_factor)
    cannot("the size floor physics.act_min_factor " + format_double(p.act_min_factor) +
           " (reached by amplitude " + format_double(amplitude_max) +
           "; voxcraft-sim has no floor)");
  std::map<Material, int> ids;
  for (const Material& m : voxel_material) ids.emplace(m, 0);
  if (static_cast<int>(ids.size()) > kVoxcraftMaxMaterials)
    throw VxaError("voxcraft export: " + std::to_string(ids.size()) +
                   " distinct (stiffness, actuation amplitude) pairs; a palette holds at most " +
                   std::to_string(kVoxcraftMaxMaterials));
  int next = 1;
  for (auto& [m, id] : ids) id = next++;
  out.materials = static_cast<int>(ids.size());
  out.max_stiffness_error = pal.max_rel_error;
  std::vector<double> quantised(robot.sites(), 0.0);
  for (size_t i = 0; i < sites.size(); ++i) quantised[sites[i]] = voxel_material[i].e;
  out.unchanged.push_back(
      "voxcraft-sim computes bonds, contacts, rotational slow damping (x1, here x" +
      format_double(p.global_damping_rot_factor) +
      "), the floor's stiffness and its fitness its own way; Poisson's ratio acts only with "
      "VolumeEffectsEnabled (docs/vxa.md, \"voxcraft-sim\")");

  // ---- base.vxa ----
  Xml b(8192);
  b.text() += "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n";
  b.open("VXA", " Version=\"1.1\"");
  b.open("Simulator");
  b.open("Integration");
  // voxcraft-sim's dt takes the stiffest bond only; plastivox's also the stiffest voxel, so
  // this DtFrac gives the same dt on the quantised robot.
  b.tag("DtFrac", p.dt_frac * voxcraft_dt_ratio(robot, quantised));
  b.close();
  write_damping(b, p);  // always: voxcraft-sim leaves them uninitialised without it
  b.open("AttachDetach");
  b.tag("EnableCollision", p.self_collision ? 1 : 0);
  b.tag("EnableAttach", 0);
  b.tag("EnableDetach", 0);
  b.close();
  b.open("StopCondition");
  b.open("StopConditionFormula");  // stop once t - duration > 0
  b.open("mtSUB");
  b.tag("mtVAR", "t");
  b.tag("mtCONST", p.duration);
  b.close();
  b.close();
  b.close();
  b.open("RecordHistory");
  b.tag("RecordStepSize", 0);
  b.tag("RecordVoxel", 1);
  b.tag("RecordLink", 0);
  b.close();
  b.tag("EnableExpansion", p.act_expansion ? 1 : 0);
  b.close();  // Simulator
  b.open("Environment");
  b.open("Gravity");
  b.tag("GravEnabled", p.gravity != 0 ? 1 : 0);  // voxcraft-sim reads only GravAcc
  b.tag("GravAcc", p.gravity);
  b.tag("FloorEnabled", p.floor ? 1 : 0);
  b.close();
  b.open("Thermal");
  b.tag("TempEnabled", 1);
  b.tag("TempAmplitude", 1);
  b.tag("TempBase", 0);
  b.tag("VaryTempEnabled", amplitude_max > 0 ? 1 : 0);
  b.tag("TempPeriod", p.act_frequency > 0 ? 1.0 / p.act_frequency : 1.0);
  b.close();
  b.close();  // Environment
  b.open("VXC", " Version=\"0.94\"");
  b.open("Lattice");
  b.tag("Lattice_Dim", robot.voxel_size);
  b.close();
  b.close();
  b.close();
  out.base_vxa = std::move(b.text());

  // ---- robot.vxd ----
  Xml v(static_cast<size_t>(robot.sites()) * 24 + 4096);
  v.open("VXD");
  v.open("Palette", " replace=\"VXA.VXC.Palette\"");
  const double lo = std::log(pal.levels.front()), span = std::log(pal.levels.back()) - lo;
  for (const auto& [m, id] : ids)
    write_material(v, m, span > 0 ? (std::log(m.e) - lo) / span : 0.5, p);
  v.close();
  v.open("Structure", " replace=\"VXA.VXC.Structure\" Compression=\"ASCII_READABLE\"");
  v.tag("X_Voxels", robot.nx);
  v.tag("Y_Voxels", robot.ny);
  v.tag("Z_Voxels", robot.nz);
  std::vector<int> id_at(robot.sites(), 0);
  for (size_t i = 0; i < sites.size(); ++i) id_at[sites[i]] = ids.at(voxel_material[i]);
  const size_t per_layer = static_cast<size_t>(robot.nx) * robot.ny;
  v.open("Data");
  for (int z = 0; z < robot.nz; ++z) {
    std::string line(per_layer, '0');
    for (size_t k = 0; k < per_layer; ++k)
      line[k] = static_cast<char>('0' + id_at[z * per_layer + k]);
    v.tag("Layer", escaped(line));
  }
  v.close();
  v.open("PhaseOffset");
  for (int z = 0; z < robot.nz; ++z) {
    std::string line;
    for (size_t k = 0; k < per_layer; ++k) {
      const size_t s = z * per_layer + k;
      if (k > 0) line += ',';
      line += format_double(robot.present[s] ? robot.phase[s] : 0.0);
    }
    v.tag("Layer", line);
  }
  v.close();
  v.close();  // Structure
  v.close();  // VXD
  out.robot_vxd = std::move(v.text());
  return out;
}

VoxcraftFiles write_voxcraft_files(const std::string& dir, const RobotDef& robot,
                                   const PhysicsDef& physics, bool lossy) {
  VoxcraftFiles files = write_voxcraft(robot, physics, lossy);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw VxaError(dir + ": cannot create the directory: " + ec.message());
  try {
    write_file_atomic((std::filesystem::path(dir) / "base.vxa").string(), files.base_vxa);
    write_file_atomic((std::filesystem::path(dir) / "robot.vxd").string(), files.robot_vxd);
  } catch (const InputError& e) {
    throw VxaError(e.what());
  }
  return files;
}

}  // namespace plastivox
