// walk, the paper's locomotion and the default task: how far the centre of mass moved from
// the end of settling to the end of the life, in voxel lengths (the summary's displacement,
// displacement_since_settling: horizontal only under physics.fitness = xy). Needs only the
// last state, so it watches nothing.
#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

class WalkWatch final : public TaskWatch {
 public:
  void see(const Model&, const State&) override {}
  double score(const Model&, const State&, const SimResult& summary) const override {
    return summary.displacement.norm();
  }
};

}  // namespace

std::unique_ptr<TaskWatch> make_walk_watch(const Model&) {
  return std::make_unique<WalkWatch>();
}

}  // namespace plastivox
