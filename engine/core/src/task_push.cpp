// push: how far the body moved a free box placed in front of it, in voxel lengths: the
// horizontal displacement of the box's centre (the mean of its voxel centres) from the end of
// settling to the end of the life,
//   |b_xy(T) - b_xy(settle)| / L.
// The box is the first free object (docs/environments.md, "Free objects"); without one in the
// environment, compile() places push_objects(): a cube of 2 x 2 x 2 voxels resting on z = 0,
// centred on the body's lattice bounds along y, its -x face one voxel length beyond the
// body's +x face. Only the box counts: a body that walks past it, or stands still, scores 0;
// a box pulled or pushed sideways counts as well.
#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {

std::vector<ObjectDef> push_objects(const RobotDef& robot) {
  int lo[3], hi[3];
  lattice_bounds(robot, lo, hi);
  const double L = robot.voxel_size;
  ObjectDef box;
  box.voxels = {2, 2, 2};
  box.at = {(hi[0] + 2) * L, 0.5 * (lo[1] + hi[1] + 1) * L - L, 0};
  return {box};
}

namespace {

class PushWatch final : public TaskWatch {
 public:
  void see(const Model& m, const State& s) override {
    if (s.settled && m.object_count() > 0) box_.add(object_center(m, s, 0));
  }
  double score(const Model& m, const State&, const SimResult&) const override {
    return box_.voxel_lengths(m);
  }

 private:
  Travel box_;  // from the end of settling
};

}  // namespace

std::unique_ptr<TaskWatch> make_push_watch(const Model&) {
  return std::make_unique<PushWatch>();
}

}  // namespace plastivox
