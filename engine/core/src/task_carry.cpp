// carry: how far the body carried a payload placed on it, in voxel lengths: from the end of
// settling to the last step the payload was still on the body, the lesser of the payload's
// horizontal displacement (of its centre, the mean of its voxel centres) and the body's (of
// its centre of mass),
//   min(|p_xy(t_last) - p_xy(settle)|, |c_xy(t_last) - c_xy(settle)|) / L.
// Both must travel: a payload that slides or bounces along the back of a body that stays
// scores what the body moved, and a body that walks out from under it what the payload did.
// "On the body" is "off the ground": every payload voxel's centre more than one voxel length
// above the ground under it (a voxel lying on the ground has its centre half a voxel up). The
// first step it is not, the payload has fallen: the score keeps what was carried before, and
// nothing after counts, even if the body picks the payload up again. A payload that is not on
// the body when settling ends scores 0.
// The payload is the first free object (docs/environments.md, "Free objects"); without one in
// the environment, compile() places carry_objects(): a slab of 2 x 2 x 1 voxels centred on
// the body's lattice bounds in x and y, its bottom on their top (it rests on whatever
// voxels of the body lie under it).
#include <algorithm>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {

std::vector<ObjectDef> carry_objects(const RobotDef& robot) {
  int lo[3], hi[3];
  ObjectDef payload = centred_object(robot, {2, 2, 1}, lo, hi);
  payload.at[2] = (hi[2] + 1) * robot.voxel_size;  // on the bounds' top
  return {payload};
}

namespace {

// Whether object k is off the ground: every voxel's centre more than L above the ground.
bool off_ground(const Model& m, const State& s, int k) {
  for (int i = m.object_begin[k]; i < m.object_begin[k + 1]; ++i) {
    const Vec3& x = s.pos[i];
    const double ground = m.terrain ? m.ground.height(x.x(), x.y()) : 0.0;
    if (!(x.z() - ground > m.size)) return false;
  }
  return true;
}

// task_values: 1 once the payload has come near the ground since settling, 1 once the
// travels are started, then the payload's travel and the body's (travel_to), from the end of
// settling while the payload is on the body (none: never on).
constexpr int kCarryDropped = 0, kCarryStarted = 1, kCarryPayload = 2, kCarryBody = 6;

}  // namespace

void see_carry(const Model& m, State& s) {
  TaskValues& v = s.task_values;
  if (!s.settled || v[kCarryDropped] != 0 || m.object_count() == 0) return;
  if (!off_ground(m, s, 0)) {
    v[kCarryDropped] = 1;
    return;
  }
  const bool first = v[kCarryStarted] == 0;
  travel_to(v, kCarryPayload, object_center(m, s, 0), first);
  travel_to(v, kCarryBody, body_center_of_mass(m, s), first);
  v[kCarryStarted] = 1;
}

double carry_score(const Model& m, const State& s, const SimResult&) {
  return std::min(travel_voxel_lengths(m, s.task_values, kCarryPayload),
                  travel_voxel_lengths(m, s.task_values, kCarryBody));
}

std::vector<const char*> carry_values() {
  return {"1 once the payload has come near the ground since settling",
          "1 once the travels are started",
          "the payload's first x, m",
          "the payload's first y, m",
          "the payload's last x, m",
          "the payload's last y, m",
          "the body's first x, m",
          "the body's first y, m",
          "the body's last x, m",
          "the body's last y, m"};
}

}  // namespace plastivox
