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
  ObjectDef box = centred_object(robot, {2, 2, 2}, lo, hi);
  box.at[0] = (hi[0] + 2) * robot.voxel_size;  // a voxel length beyond the bounds' +x face
  return {box};
}

namespace {

// task_values: the box's travel from the end of settling (travel_to), once started.
constexpr int kPushStarted = 0, kPushBox = 1;

}  // namespace

void see_push(const Model& m, State& s) {
  if (!s.settled || m.object_count() == 0) return;
  travel_to(s.task_values, kPushBox, object_center(m, s, 0), s.task_values[kPushStarted] == 0);
  s.task_values[kPushStarted] = 1;
}

double push_score(const Model& m, const State& s, const SimResult&) {
  return travel_voxel_lengths(m, s.task_values, kPushBox);
}

std::vector<const char*> push_values() {
  return {"1 once the box's travel is started (settled)", "the box's first x, m",
          "the box's first y, m", "the box's last x, m", "the box's last y, m"};
}

}  // namespace plastivox
