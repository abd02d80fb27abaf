#include "plastivox/analysis/voxel_set.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace plastivox::analysis {

VoxelSet voxel_set(const RobotDef& robot) {
  if (static_cast<int>(robot.present.size()) != robot.sites())
    throw std::invalid_argument("voxel_set: robot '" + robot.name + "' has " +
                                std::to_string(robot.present.size()) + " presence flags for " +
                                std::to_string(robot.sites()) + " lattice sites");
  VoxelSet s;
  s.lattice = {robot.nx, robot.ny, robot.nz};
  for (int z = 0; z < robot.nz; ++z)
    for (int y = 0; y < robot.ny; ++y)
      for (int x = 0; x < robot.nx; ++x)
        if (robot.present[robot.site(x, y, z)]) s.voxels.push_back({x, y, z});
  return s;
}

namespace {

// "(-y,x,z)": row i of the matrix picks one signed source axis.
std::string image_name(const std::array<std::array<int, 3>, 3>& m) {
  std::string s = "(";
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      if (m[i][j] != 0) {
        if (m[i][j] < 0) s += '-';
        s += "xyz"[j];
      }
    s += i < 2 ? "," : ")";
  }
  return s;
}

Rotation from_matrix(const std::array<std::array<int, 3>, 3>& m) {
  Rotation r;
  r.m = m;
  r.name = image_name(m);
  return r;
}

int determinant(const std::array<std::array<int, 3>, 3>& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

}  // namespace

Rotation compose(const Rotation& outer, const Rotation& inner) {
  std::array<std::array<int, 3>, 3> m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) m[i][j] += outer.m[i][k] * inner.m[k][j];
  return from_matrix(m);
}

Rotation inverse(const Rotation& r) {
  std::array<std::array<int, 3>, 3> m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[i][j] = r.m[j][i];
  return from_matrix(m);
}

bool operator==(const Rotation& a, const Rotation& b) {
  return a.m == b.m;
}

const std::vector<Rotation>& identity_rotations() {
  static const std::vector<Rotation> set = {from_matrix({{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}})};
  return set;
}

const std::vector<Rotation>& paper_rotations() {
  static const std::vector<Rotation> set = [] {
    const Rotation z = from_matrix({{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}});     // (x,y) -> (-y,x)
    const Rotation turn = from_matrix({{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}});  // (y,z) -> (-z,y)
    std::vector<Rotation> out;
    Rotation zk = identity_rotations()[0];
    for (int k = 0; k < 4; ++k) {
      out.push_back(zk);
      out.push_back(compose(turn, zk));
      zk = compose(z, zk);
    }
    return out;
  }();
  return set;
}

const std::vector<Rotation>& cube_rotations() {
  static const std::vector<Rotation> set = [] {
    // Every signed permutation matrix with determinant +1, sorted lexicographically; then
    // the identity moved to the front.
    std::vector<std::array<std::array<int, 3>, 3>> mats;
    std::array<int, 3> perm = {0, 1, 2};
    do {
      for (int signs = 0; signs < 8; ++signs) {
        std::array<std::array<int, 3>, 3> m{};
        for (int i = 0; i < 3; ++i) m[i][perm[i]] = (signs >> i) & 1 ? -1 : 1;
        if (determinant(m) == 1) mats.push_back(m);
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
    std::sort(mats.begin(), mats.end());
    std::vector<Rotation> out = identity_rotations();
    for (const auto& m : mats)
      if (!(m == out[0].m)) out.push_back(from_matrix(m));
    return out;
  }();
  return set;
}

Voxel lattice_shift(const Voxel& lattice, const Rotation& r) {
  Voxel lo = {0, 0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    Voxel c{};
    for (int k = 0; k < 3; ++k) c[k] = (corner >> k) & 1 ? lattice[k] - 1 : 0;
    const Voxel rc = rotate_voxel(r, c);
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], rc[k]);
  }
  return {-lo[0], -lo[1], -lo[2]};
}

VoxelSet rotate_in_lattice(const VoxelSet& set, const Rotation& r) {
  const Voxel s = lattice_shift(set.lattice, r);
  VoxelSet out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (r.m[i][j] != 0) out.lattice[i] = set.lattice[j];
  out.voxels.reserve(set.voxels.size());
  for (const Voxel& p : set.voxels) {
    const Voxel q = rotate_voxel(r, p);
    out.voxels.push_back({q[0] + s[0], q[1] + s[1], q[2] + s[2]});
  }
  // Keep the documented order (increasing site, x fastest).
  std::sort(out.voxels.begin(), out.voxels.end(), [](const Voxel& a, const Voxel& b) {
    return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
  });
  return out;
}

}  // namespace plastivox::analysis
