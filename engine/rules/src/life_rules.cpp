#include "plastivox/rules/life_rules.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace plastivox {
namespace {

// The floor's health warning the core gives a sunk life ("sank through the floor: ..."), the
// first part of its failure when the rule makes it invalid.
std::string sank_warning(const SimResult& r) {
  for (const std::string& w : r.warnings)
    if (w.starts_with("sank through the floor")) return w;
  return "sank through the floor";
}

}  // namespace

bool vertical_exploit(const PhysicsDef& def, const SimResult& r) {
  return def.task == Task::kWalk && def.fitness == FitnessMode::k3D &&
         r.status == SimStatus::kFinished && !r.sank && r.vertical_share > kVerticalShareLimit &&
         std::abs(r.displacement.z()) >= kVerticalRiseMin;
}

void judge_life(const PhysicsDef& def, SimResult& r) {
  if (r.status == SimStatus::kFinished && r.sank && def.sinking_invalid) {
    r.status = SimStatus::kUnstable;
    r.failure = sank_warning(r) +
                " (sunk lives are invalid: physics.sinking_invalid; false restores the "
                "authors' rule, which scores them)";
    r.fitness = 0;
  }
  // Only a life that counts succeeds (the core claims success for finished lives alone).
  if (r.status != SimStatus::kFinished) r.success = false;
  // Said, as the floor's health is, since the number alone reads as a walk (without the
  // floor nothing holds a body up unless boxes do).
  if (!vertical_exploit(def, r)) return;
  char buf[480];
  std::snprintf(buf, sizeof buf,
                "fitness owes too much to vertical motion (vertical share %.3f, above the limit "
                "%.2g; dz %.4g voxel lengths)%s: walk's 3-D fitness scores a rise or a fall as "
                "distance, and a study excludes such a champion (docs/engine.md, \"Vertical "
                "motion\"); fitness \"xy\" scores horizontal travel only",
                r.vertical_share, kVerticalShareLimit, r.displacement.z(),
                def.floor ? "" : ", physics.floor is false so nothing holds the body up");
  r.warnings.push_back(buf);
}

bool ends_invalid(const PhysicsDef& def, bool sunk) {
  return def.sinking_invalid && sunk;
}

}  // namespace plastivox
