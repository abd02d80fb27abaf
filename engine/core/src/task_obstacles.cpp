// obstacles: cross a field of static blocks. The fitness is the horizontal displacement of
// the centre of mass from the end of settling to the end of the life, in voxel lengths,
//   |c_xy(T) - c_xy(settle)| / L
// (as rough's): the blocks are what makes it hard.
//
// Default environment: the flat floor and a field of blocks around the start. The plane is
// cut into squares of side `spacing`, one centred on the body's footprint, out to kFieldReach
// voxel lengths past the footprint (at most kFieldMaxSide squares a side). Each square holds one
// block, `size` wide and deep and `height` tall (standing on the floor; its hidden part goes
// a voxel length below it), at a place drawn from `seed` within its square. Blocks that would
// come within kFieldClear voxel lengths of the footprint are left out, so the body starts on open
// ground. Every square draws its place whether or not its block is left out, so bodies of
// every size meet the same field.
#include <algorithm>
#include <cmath>

#include "plastivox/base/rng.hpp"
#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kFieldReach = 20;  // voxel lengths of field past the footprint
constexpr double kFieldClear = 1;   // voxel lengths of open ground around the footprint
constexpr int kFieldMaxSide = 63;   // squares a side at most (63^2 < kMaxObstacles)
// The stream the blocks' places are drawn from (Rng::stream's purpose).
constexpr uint64_t kBlockStream = 0x626c6f636b73;  // "blocks"

}  // namespace

std::vector<TaskParam> obstacles_params() {
  return {{"height", 0.5, 0.05, 5, "voxel lengths"},
          {"size", 1, 0.25, 5, "voxel lengths"},
          {"spacing", 3, 1, 20, "voxel lengths"},
          {"seed", 1, 0, 9007199254740992.0, "", true}};
}

Environment obstacles_environment(const PhysicsDef& def, const TaskSite& site) {
  const double L = site.L, spacing = task_param(def, "spacing") * L;
  const double size = task_param(def, "size") * L, height = task_param(def, "height") * L;
  const int k = std::min(kFieldMaxSide / 2,
                         static_cast<int>(std::ceil((site.half() + kFieldReach * L) / spacing)));
  const double play = std::max(0.0, spacing - size);  // room to move within a square, m
  Rng rng = Rng::stream(static_cast<uint64_t>(task_param(def, "seed")), kBlockStream, 0, 0);
  Environment env;
  for (int b = -k; b <= k; ++b)
    for (int a = -k; a <= k; ++a) {
      const double x = site.cx + a * spacing + play * (rng.uniform() - 0.5);
      const double y = site.cy + b * spacing + play * (rng.uniform() - 0.5);
      const double gap = kFieldClear * L + 0.5 * size;  // centre to footprint, at least
      if (std::abs(x - site.cx) < site.hx + gap && std::abs(y - site.cy) < site.hy + gap) continue;
      env.obstacles.push_back(
          {{x - 0.5 * size, y - 0.5 * size, -L}, {x + 0.5 * size, y + 0.5 * size, height}});
    }
  return env;
}

}  // namespace plastivox
