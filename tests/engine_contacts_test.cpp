// Self-collision candidates (engine/core/src/contacts.cpp) are refreshed voxel by voxel; the forces
// are exact only if every touching pair is a candidate at every step. Checked against brute
// force over all surface pairs, step by step, on bodies that fold onto themselves.
#include <algorithm>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simulator.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

// Steps the life in its two halves, checking the candidates between them (after the contact
// stage). Returns the number of (step, touching pair) checks made.
long check_every_touching_pair_is_listed(const Model& m, int steps) {
  Simulator sim(m);
  const State& s = sim.state();
  const double half_d = 0.5 * m.def.contact_diameter;
  std::vector<int> surface;
  for (int i = 0; i < m.n; ++i)
    if (m.surface[i]) surface.push_back(i);
  long touching = 0;
  for (int step = 0; step < steps && s.status == SimStatus::kRunning; ++step) {
    sim.step1();
    const auto& partners = sim.workspace().contact_grid.partners;
    for (size_t a = 0; a < surface.size(); ++a) {
      for (size_t b = a + 1; b < surface.size(); ++b) {
        const int i = surface[a], j = surface[b];
        const double contact = half_d * (s.size[i] + s.size[j]);
        if ((s.pos[j] - s.pos[i]).squaredNorm() >= contact * contact) continue;
        if (std::binary_search(m.near_voxels[i].begin(), m.near_voxels[i].end(), j)) continue;
        ++touching;
        if (!std::binary_search(partners[i].begin(), partners[i].end(), j)) {
          ADD_FAILURE() << "pair (" << i << ", " << j << ") touches at step " << step
                        << " but is not listed";
          return -1;
        }
      }
    }
    sim.step2();
  }
  return touching;
}

TEST(SelfCollision, EveryTouchingPairIsACandidateSoftCrushedBody) {
  // Paper preset (down to 1e4 Pa): the body collapses and its soft voxels flap and fold.
  PhysicsDef d = preset_gecco2018_paper();
  d.treatment = Treatment::kStress;
  const long touching =
      check_every_touching_pair_is_listed(compile(demo_irregular(300, 3), d), 3000);
  EXPECT_GT(touching, 1000);  // the check is not vacuous
}

TEST(SelfCollision, EveryTouchingPairIsACandidateWalker) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kPressure;
  const long touching =
      check_every_touching_pair_is_listed(compile(demo_irregular(500, 7), d), 3000);
  EXPECT_GT(touching, 1000);
}

}  // namespace
}  // namespace plastivox
