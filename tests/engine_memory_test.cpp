// Memory grows with voxels, not lattice sites (issue 14): a one-voxel robot declared in the
// largest lattice allowed is loaded, compiled and simulated while a counting allocator (this
// binary's operator new) records the peak of live heap bytes. The robot's own arrays are
// dense by definition (RobotDef: 25 bytes a site, robot.hpp); everything past them, the
// compiled model and the simulation, must cost memory per voxel.
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>

#include "plastivox/io/robot_file.hpp"
#include "plastivox/model.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace {

// Live and peak heap bytes through operator new (every std container allocates there). A
// header before each block holds its size; the header is as wide as the block's alignment.
size_t g_live = 0, g_peak = 0;

void* counted_new(size_t bytes, size_t align) {
  const size_t header = align < sizeof(size_t) * 2 ? sizeof(size_t) * 2 : align;
  void* raw = std::aligned_alloc(header, ((header + bytes + header - 1) / header) * header);
  if (!raw) throw std::bad_alloc();
  *static_cast<size_t*>(raw) = bytes;
  g_live += bytes;
  if (g_live > g_peak) g_peak = g_live;
  return static_cast<char*>(raw) + header;
}

void counted_delete(void* p, size_t align) noexcept {
  if (!p) return;
  const size_t header = align < sizeof(size_t) * 2 ? sizeof(size_t) * 2 : align;
  void* raw = static_cast<char*>(p) - header;
  g_live -= *static_cast<size_t*>(raw);
  std::free(raw);
}

// Peak bytes allocated above what was live when it was constructed.
class PeakScope {
 public:
  PeakScope() : base_(g_live) { g_peak = g_live; }
  size_t peak() const { return g_peak - base_; }

 private:
  size_t base_;
};

}  // namespace

void* operator new(size_t n) {
  return counted_new(n, 0);
}
void* operator new[](size_t n) {
  return counted_new(n, 0);
}
void* operator new(size_t n, std::align_val_t a) {
  return counted_new(n, static_cast<size_t>(a));
}
void* operator new[](size_t n, std::align_val_t a) {
  return counted_new(n, static_cast<size_t>(a));
}
void operator delete(void* p) noexcept {
  counted_delete(p, 0);
}
void operator delete[](void* p) noexcept {
  counted_delete(p, 0);
}
void operator delete(void* p, size_t) noexcept {
  counted_delete(p, 0);
}
void operator delete[](void* p, size_t) noexcept {
  counted_delete(p, 0);
}
void operator delete(void* p, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete[](void* p, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete(void* p, size_t, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}
void operator delete[](void* p, size_t, std::align_val_t a) noexcept {
  counted_delete(p, static_cast<size_t>(a));
}

namespace plastivox {
namespace {

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
