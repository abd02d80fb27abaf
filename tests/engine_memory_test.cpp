// Memory grows with voxels, not lattice sites (issue 14): a one-voxel robot declared in the
// largest lattice allowed is loaded, compiled and simulated while a counting allocator (this
// binary's operator new) records the peak of live heap bytes. The robot's own arrays are
// dense by definition (RobotDef: 25 bytes a site, robot.hpp); everything past them, the
// compiled model and the simulation, must cost memory per voxel.
#include <string>

#include <gtest/gtest.h>

#include "counting_new.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/model.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {
namespace {

using test::PeakScope;

TEST(Memory, OneVoxelInTheLargestLatticeCostsPerVoxelPastTheRobotsArrays) {
  // 128^3 = 2^21 sites, the default cap (Limits::lattice_sites), one voxel in a corner.
  const int e = 128;
  const std::string text =
      R"({"format":"plastivox-robot","version":1,"lattice":{"nx":128,"ny":128,"nz":128,
          "voxel_size":0.01},"voxels":[[5,7,9,1e6,0,0]],
          "physics":{"duration":0.05,"settle_time":0}})";
  const size_t sites = size_t{e} * e * e;
  ASSERT_EQ(static_cast<int64_t>(sites), Limits{}.lattice_sites);
  // The robot's dense arrays (present u8, stiffness, dev_rate and phase f64): 25 B a site.
  const size_t robot_arrays = sites * (1 + 3 * sizeof(double));
  const size_t slack = 64 << 10;  // JSON text and tree, names, messages: per voxel

  RobotFile file;
  {
    const PeakScope load;
    file = parse_robot_json(text, "big.json");
    EXPECT_LE(load.peak(), robot_arrays + slack) << "loading allocates beyond the robot itself";
    EXPECT_GE(load.peak(), robot_arrays);  // the counter sees the arrays it must
  }
  ASSERT_EQ(file.robot.voxel_count(), 1);

  // Compiling and simulating: nothing per site (compile's site -> voxel table was 4 B a
  // site, 8 MiB here).
  const PeakScope run;
  const Model model = compile(file.robot, file.physics);
  ASSERT_EQ(model.n, 1);
  EXPECT_LE(run.peak(), slack) << "compile allocates per lattice site";
  const SimResult r = simulate(model);
  EXPECT_EQ(r.status, SimStatus::kFinished);
  EXPECT_GT(r.steps, 0);
  EXPECT_LE(run.peak(), slack) << "the simulation allocates per lattice site";
}

}  // namespace
}  // namespace plastivox
