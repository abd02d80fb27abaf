// jump: the highest rise of the centre of mass above its settled height, in voxel lengths:
//   max over the steps after settling of (c_z(t) - c_z(settle)) / L,
// c the mean of the voxel centres (every voxel has one mass), L the voxel size. It is never
// negative: the first state seen after settling is the settled one. A body that sinks or
// topples scores what it rose before, not less.
#include <algorithm>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

class JumpWatch final : public TaskWatch {
 public:
  void see(const Model& m, const State& s) override {
    if (s.settled) highest_ = std::max(highest_, body_center_of_mass(m, s).z() - s.com_settled.z());
  }
  double score(const Model& m, const State&, const SimResult&) const override {
    return highest_ / m.size;
  }

 private:
  double highest_ = 0;  // m above the settled centre of mass, the most seen
};

}  // namespace

std::unique_ptr<TaskWatch> make_jump_watch(const Model&) {
  return std::make_unique<JumpWatch>();
}

}  // namespace plastivox
