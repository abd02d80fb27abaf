#include "plastivox/demo_robots.hpp"

#include <cmath>
#include <cstdint>
#include <functional>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/base/rng.hpp"

namespace plastivox {

RobotDef demo_walker() {
  RobotDef r = make_empty_robot(10, 10, 10);
  r.name = "demo-walker";
  for (int z = 0; z < 8; ++z)
    for (int y = 1; y < 9; ++y)
      for (int x = 0; x < 10; ++x) {
        const bool slab = z >= 4;
        const bool leg = x <= 2 || x >= 7;
        if (!slab && !leg) continue;
        const int s = r.site(x, y, z);
        r.present[s] = 1;
        // Smooth fields from the lattice coordinates (like a CPPN would make them). Under the
        // presets' density (1e9 kg/m^3) a leg must be near 1e10 Pa to carry the slab, and a
        // rate that softens a loaded voxel folds it within a second, so E0 spans 7e9..1e10 Pa
        // and development only stiffens under load (rate 0..6 1/s): a callus, not a collapse.
        const double u = x / 9.0, v = y / 9.0, w = z / 9.0;
        const double log_e = 9.85 + 0.15 * std::sin(3.0 * u + 2.0 * w) * std::cos(2.5 * v);
        r.stiffness[s] = std::pow(10.0, log_e);
        r.dev_rate[s] = 3.0 + 3.0 * std::sin(4.0 * u - 3.0 * w + v);
        r.phase[s] = 0.9 * (u - 0.5) + 0.2 * w;
      }
  return r;
}

RobotDef demo_cube(int n, double E) {
  RobotDef r = make_empty_robot(n, n, n);
  r.name = "demo-cube";
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = E;
    r.phase[s] = (s % n) / static_cast<double>(n) - 0.5;
  }
  return r;
}

RobotDef demo_irregular(int target, unsigned seed) {
  RobotDef r = make_empty_robot(10, 10, 10);
  r.name = "demo-irregular";
  Rng rng(seed * 0x2545f4914f6cdd1dull + 1);
  // Grow a face-connected body from the bottom centre by random accretion.
  std::vector<int> body{r.site(5, 5, 0)};
  r.present[body[0]] = 1;
  const int dx[6] = {1, -1, 0, 0, 0, 0}, dy[6] = {0, 0, 1, -1, 0, 0}, dz[6] = {0, 0, 0, 0, 1, -1};
  while (static_cast<int>(body.size()) < target && static_cast<int>(body.size()) < r.sites()) {
    const int s = body[rng.next_u64() % body.size()];
    const int k = static_cast<int>(rng.next_u64() % 6);
    const int x = s % 10 + dx[k], y = (s / 10) % 10 + dy[k], z = s / 100 + dz[k];
    if (x < 0 || y < 0 || z < 0 || x > 9 || y > 9 || z > 9) continue;
    const int t = r.site(x, y, z);
    if (r.present[t]) continue;
    r.present[t] = 1;
    body.push_back(t);
  }
  for (int s : body) {
    r.stiffness[s] = std::pow(10.0, 5.0 + 6.0 * rng.uniform());
    r.dev_rate[s] = -10.0 + 20.0 * rng.uniform();
    r.phase[s] = 2.0 * rng.uniform() - 1.0;
  }
  return r;
}

namespace {

// An nx*ny*nz lattice holding the cells where `inside` is true, log10 of stiffness from
// `log_e`, a smooth development rate 10 sin(4u - 3w + v) and demo_walker's phase field.
RobotDef shaped(const std::string& name, int nx, int ny, int nz,
                const std::function<bool(int, int, int)>& inside,
                const std::function<double(int, int, int)>& log_e) {
  RobotDef r = make_empty_robot(nx, ny, nz);
  r.name = name;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (!inside(x, y, z)) continue;
        const int s = r.site(x, y, z);
        const double u = x / (nx - 1.0), v = y / (ny - 1.0), w = z / (nz - 1.0);
        r.present[s] = 1;
        r.stiffness[s] = std::pow(10.0, log_e(x, y, z));
        r.dev_rate[s] = 10.0 * std::sin(4.0 * u - 3.0 * w + v);
        r.phase[s] = 0.9 * (u - 0.5) + 0.2 * w;
      }
  return r;
}

// 1e9..1e10 Pa, varying smoothly with the cell: stiff enough to keep its shape.
double smooth_log_e(int x, int y, int z) {
  return 9.5 + 0.5 * std::sin(0.7 * x + 0.4 * z) * std::cos(0.5 * y);
}

}  // namespace

const std::vector<std::string>& demo_example_names() {
  static const std::vector<std::string> names{"walker", "pi", "gamma", "upsilon", "mixture"};
  return names;
}

RobotDef demo_example(const std::string& name) {
  if (name == "walker") return demo_walker();
  if (name == "pi")  // front and back legs 3 wide under a 3-high bridge, a 4x4 gap
    return shaped(
        "example-pi", 10, 8, 7, [](int x, int, int z) { return x < 3 || x >= 7 || z >= 4; },
        smooth_log_e);
  if (name == "gamma")  // side view "L": a 3-thick wall on a 3-thick floor plate
    return shaped(
        "example-gamma", 10, 8, 8, [](int x, int, int z) { return x < 3 || z < 3; }, smooth_log_e);
  if (name == "upsilon")  // a 10x10 upright plate, 2 thick, a rod of radius 2.5 from its centre
    return shaped(
        "example-upsilon", 10, 10, 10,
        [](int x, int y, int z) {
          const int dy = 2 * y - 9, dz = 2 * z - 9;  // twice the offset from the centre 4.5
          return x < 2 || dy * dy + dz * dz <= 25;
        },
        smooth_log_e);
  if (name == "mixture")  // a four-legged table of soft (1e8 Pa) and stiff (1e10 Pa) 2x2x2 blocks
    return shaped(
        "example-mixture", 10, 8, 6,
        [](int x, int y, int z) { return z >= 3 || ((x < 3 || x >= 7) && (y < 3 || y >= 5)); },
        [](int x, int y, int z) { return (x / 2 + y / 2 + z / 2) % 2 ? 8.0 : 10.0; });
  std::string known;
  for (const std::string& n : demo_example_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown example robot '" + name + "' (known: " + known + ")");
}

}  // namespace plastivox
