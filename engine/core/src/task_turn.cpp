// turn: the body's net rotation about the vertical axis from the end of settling to the end
// of the life, in radians, |theta(T)|, either way round.
//
// A soft body has no one orientation: each voxel turns on its own as the body flexes, and a
// principal axis of the footprint is undefined for a square one. The turn used here is the
// rotation about z that best carries the body's settled horizontal layout onto its present
// one. With r0_i the horizontal offset of voxel i's centre from the centre of mass when
// settling ended, and r_i its offset now, the least-squares angle (2-D Procrustes) is
//   theta = atan2(sum_i r0_i x r_i, sum_i r0_i . r_i).
// It is exact for a rigid turn, ignores where the body walked (offsets from the centre of
// mass) and its tilt (x and y only), and weighs every voxel alike. atan2 wraps at ±pi, so
// the watch follows (dot, cross) every step and counts whole turns as it crosses the
// negative dot axis (a step turns a body far less than half a turn). A body whose voxel
// centres all lie on one vertical line has no layout to turn, and scores 0.
#include <cmath>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kTwoPi = 6.283185307179586476925287;

class TurnWatch final : public TaskWatch {
 public:
  void see(const Model& m, const State& s) override {
    if (!s.settled) return;
    if (x0_.empty()) {  // the first state after settling: the layout turns are measured from
      x0_.resize(m.robot_n);
      y0_.resize(m.robot_n);
      for (int i = 0; i < m.robot_n; ++i) {
        x0_[i] = s.pos[i].x() - s.com_settled.x();
        y0_[i] = s.pos[i].y() - s.com_settled.y();
      }
    }
    const Vec3 c = body_center_of_mass(m, s);
    double dot = 0, cross = 0;
    for (int i = 0; i < m.robot_n; ++i) {
      const double x = s.pos[i].x() - c.x(), y = s.pos[i].y() - c.y();
      dot += x0_[i] * x + y0_[i] * y;
      cross += x0_[i] * y - y0_[i] * x;
    }
    // Through +pi (cross from >= 0 to < 0 behind the axis) is a whole turn more; back, one less.
    if (dot < 0 && (cross < 0) != (cross_ < 0)) turns_ += cross < 0 ? 1 : -1;
    dot_ = dot;
    cross_ = cross;
  }

  double score(const Model&, const State&, const SimResult&) const override {
    if (x0_.empty()) return 0;  // never settled
    // cross_ == 0 behind the axis is +pi, as the count above takes it (not -pi for -0.0).
    const double theta = std::atan2(cross_ == 0 ? 0.0 : cross_, dot_) + kTwoPi * turns_;
    return std::abs(theta);
  }

 private:
  std::vector<double> x0_, y0_;  // settled horizontal offsets from the centre of mass, m
  double dot_ = 0, cross_ = 0;   // sums at the last state seen, m^2
  long turns_ = 0;               // whole turns counted, + anticlockwise seen from above
};

}  // namespace

std::unique_ptr<TaskWatch> make_turn_watch(const Model&) {
  return std::make_unique<TurnWatch>();
}

}  // namespace plastivox
