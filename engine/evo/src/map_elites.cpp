// MAP-Elites' descriptors and cells (map_elites.hpp).
#include "plastivox/evo/map_elites.hpp"

#include <cmath>
#include <limits>

#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/model.hpp"
#include "plastivox/state.hpp"

namespace plastivox::evo {

void DescriptorWatch::see(const State& s) {
  if (s.time < next_) return;
  while (next_ <= s.time) next_ += kLifeSampleInterval;  // several sample times in one step: one
  const Model& m = model_;
  const int n = m.robot_n;
  int touching = 0;
  if (m.def.floor)
    for (int i = 0; i < n; ++i) {
      const Vec3& x = s.pos[i];
      touching += m.ground.penetration(x.x(), x.y(), x.z(), 0.5 * s.size[i]) > 0 ? 1 : 0;
    }
  const Vec3 com = body_center_of_mass(m, s);
  contact_sum_ += n > 0 ? static_cast<double>(touching) / n : 0.0;
  height_sum_ += (com.z() - m.ground.height(com.x(), com.y())) / m.size;
  ++samples_;
}

DescriptorMeasures DescriptorWatch::finish(double development) const {
  DescriptorMeasures out;
  out.measured = true;
  if (samples_ > 0) {
    out.floor_contact = contact_sum_ / static_cast<double>(samples_);
    out.com_height = height_sum_ / static_cast<double>(samples_);
  }
  out.development = development;
  return out;
}

bool from_life(Descriptor d) {
  return d == Descriptor::kDevelopment || d == Descriptor::kFloorContact ||
         d == Descriptor::kComHeight;
}

bool needs_life(const MapElitesSettings& s) {
  for (const DescriptorAxis& a : s.axes)
    if (from_life(a.what)) return true;
  return false;
}

std::vector<double> body_descriptors(const MapElitesSettings& s, const Phenotype& p) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> out(s.axes.size(), nan);
  const RobotDef& r = p.robot;
  if (!p.valid || p.voxels < 1) return out;
  bool plans = false;
  for (const DescriptorAxis& a : s.axes)
    plans |=
        a.what == Descriptor::kPi || a.what == Descriptor::kGamma || a.what == Descriptor::kUpsilon;
  analysis::BodyPlanResult plan;
  if (plans) plan = analysis::classify_body_plan(analysis::voxel_set(r));
  double stiffness = 0;  // summed in site order
  for (int i = 0; i < r.sites(); ++i)
    if (r.present[i]) stiffness += r.stiffness[i];
  for (size_t k = 0; k < s.axes.size(); ++k) {
    switch (s.axes[k].what) {
      case Descriptor::kVoxels:
        out[k] = p.voxels;
        break;
      case Descriptor::kFill:
        out[k] = static_cast<double>(p.voxels) / r.sites();
        break;
      case Descriptor::kPi:
        out[k] = plan.features.matches[0].score;
        break;
      case Descriptor::kGamma:
        out[k] = plan.features.matches[1].score;
        break;
      case Descriptor::kUpsilon:
        out[k] = plan.features.matches[2].score;
        break;
      case Descriptor::kStiffness:
        out[k] = stiffness / p.voxels;
        break;
      default:  // the life's
        break;
    }
  }
  return out;
}

void life_descriptors(const MapElitesSettings& s, const DescriptorMeasures& life,
                      std::vector<double>& values) {
  if (!life.measured) return;
  for (size_t k = 0; k < s.axes.size(); ++k) {
    switch (s.axes[k].what) {
      case Descriptor::kDevelopment:
        values[k] = life.development;
        break;
      case Descriptor::kFloorContact:
        values[k] = life.floor_contact;
        break;
      case Descriptor::kComHeight:
        values[k] = life.com_height;
        break;
      default:  // the body's
        break;
    }
  }
}

int64_t cell_of(const MapElitesSettings& s, const std::vector<double>& values) {
  int64_t cell = 0;
  for (size_t k = 0; k < s.axes.size(); ++k) {
    const DescriptorAxis& a = s.axes[k];
    const double v = values[k];
    if (std::isnan(v)) return -1;
    const double at = std::floor((v - a.lo) / (a.hi - a.lo) * a.bins);
    const int bin = at < 0 ? 0 : at >= a.bins ? a.bins - 1 : static_cast<int>(at);
    cell = cell * a.bins + bin;
  }
  return cell;
}

std::vector<int> bins_of(const MapElitesSettings& s, int64_t cell) {
  std::vector<int> bins(s.axes.size());
  for (size_t k = s.axes.size(); k-- > 0;) {
    bins[k] = static_cast<int>(cell % s.axes[k].bins);
    cell /= s.axes[k].bins;
  }
  return bins;
}

}  // namespace plastivox::evo
