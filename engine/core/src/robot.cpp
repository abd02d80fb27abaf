#include "plastivox/robot.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace plastivox {

int RobotDef::voxel_count() const {
  int n = 0;
  for (uint8_t p : present) n += p ? 1 : 0;
  return n;
}

void check_lattice_size(int nx, int ny, int nz, const Limits& limits) {
  if (nx < 1 || ny < 1 || nz < 1 || nx > 1000 || ny > 1000 || nz > 1000)
    throw std::invalid_argument("robot.size: lattice extent must be 1..1000 in each axis");
  const int64_t limit = limits.lattice_sites;
  const int64_t sites = int64_t{nx} * ny * nz;
  if (sites > limit)
    throw std::invalid_argument(
        "robot.size: a " + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
        std::to_string(nz) + " lattice has " + std::to_string(sites) +
        " sites, more than the limit of " + std::to_string(limit) +
        " (the environment variable PLASTIVOX_MAX_LATTICE_SITES raises it)");
}

RobotDef make_empty_robot(int nx, int ny, int nz, double voxel_size, const Limits& limits) {
  check_lattice_size(nx, ny, nz, limits);
  RobotDef r;
  r.nx = nx;
  r.ny = ny;
  r.nz = nz;
  r.voxel_size = voxel_size;
  const size_t n = static_cast<size_t>(nx) * ny * nz;
  r.present.assign(n, 0);
  r.stiffness.assign(n, 0.0);
  r.dev_rate.assign(n, 0.0);
  r.phase.assign(n, 0.0);
  return r;
}

void validate(const RobotDef& r, const Limits& limits) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw std::invalid_argument("robot." + field + ": " + what);
  };
  check_lattice_size(r.nx, r.ny, r.nz, limits);
  if (!(r.voxel_size >= kMinVoxelSize && r.voxel_size <= kMaxVoxelSize))
    fail("voxel_size", "must be in [1e-4, 10] m");
  const size_t n = static_cast<size_t>(r.sites());
  if (r.present.size() != n) fail("present", "expected " + std::to_string(n) + " entries");
  if (r.stiffness.size() != n) fail("stiffness", "expected " + std::to_string(n) + " entries");
  if (r.dev_rate.size() != n) fail("dev_rate", "expected " + std::to_string(n) + " entries");
  if (r.phase.size() != n) fail("phase", "expected " + std::to_string(n) + " entries");
  const bool own_amplitude = !r.act_amplitude.empty();
  if (own_amplitude && r.act_amplitude.size() != n)
    fail("act_amplitude", "expected " + std::to_string(n) + " entries or none");
  const bool scaled = !r.act_scale.empty();
  if (scaled && r.act_scale.size() != n)
    fail("act_scale", "expected " + std::to_string(n) + " entries or none");
  for (size_t i = 0; i < n; ++i) {
    if (!r.present[i]) continue;
    if (scaled && !(r.act_scale[i] >= 0 && r.act_scale[i] <= 1))
      fail("act_scale[" + std::to_string(i) + "]", "must be in [0, 1]");
    if (!(r.stiffness[i] > 0) || !std::isfinite(r.stiffness[i]))
      fail("stiffness[" + std::to_string(i) + "]", "must be a positive finite modulus in Pa");
    if (!std::isfinite(r.dev_rate[i])) fail("dev_rate[" + std::to_string(i) + "]", "not finite");
    if (!std::isfinite(r.phase[i])) fail("phase[" + std::to_string(i) + "]", "not finite");
    if (own_amplitude && !(r.act_amplitude[i] >= 0 && r.act_amplitude[i] < 0.9))
      fail("act_amplitude[" + std::to_string(i) + "]", "must be in [0, 0.9)");
  }
  if (r.voxel_count() == 0) fail("present", "the robot has no voxels");
  try {
    validate(r.controller);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("robot.") + e.what());
  }
  for (size_t k = 0; k < r.fixed_sites.size(); ++k) {
    const int s = r.fixed_sites[k];
    if (s < 0 || static_cast<size_t>(s) >= n || !r.present[s])
      fail("fixed_sites[" + std::to_string(k) + "]", "names a site without a voxel");
  }
  for (size_t k = 0; k < r.loads.size(); ++k) {
    const RobotDef::Load& l = r.loads[k];
    if (l.site < 0 || static_cast<size_t>(l.site) >= n || !r.present[l.site])
      fail("loads[" + std::to_string(k) + "].site", "names a site without a voxel");
    if (!std::isfinite(l.fx) || !std::isfinite(l.fy) || !std::isfinite(l.fz))
      fail("loads[" + std::to_string(k) + "]", "force is not finite");
  }
}

}  // namespace plastivox
