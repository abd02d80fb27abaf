// Body-plan classification: features, the four orientations, and the verdict (rule in
// body_plan.hpp; templates in body_plan_templates.cpp).
#include <algorithm>
#include <functional>
#include <stdexcept>

#include "body_plan_templates.hpp"
#include "plastivox/analysis/body_plan.hpp"

namespace plastivox::analysis {

namespace {

// Each body plan's name and symbol, in one place.
struct PlanNames {
  BodyPlan plan;
  const char* name;
  const char* symbol;  // UTF-8
};
constexpr PlanNames kPlanNames[] = {{BodyPlan::kPi, "Pi", "Π"},
                                    {BodyPlan::kGamma, "Gamma", "Γ"},
                                    {BodyPlan::kUpsilon, "Upsilon", "Υ"},
                                    {BodyPlan::kOther, "other", "other"}};

}  // namespace

const char* to_string(BodyPlan p) {
  for (const PlanNames& n : kPlanNames)
    if (n.plan == p) return n.name;
  return "?";
}

const char* symbol(BodyPlan p) {
  for (const PlanNames& n : kPlanNames)
    if (n.plan == p) return n.symbol;
  return "?";
}

namespace {

// Sizes of the 4-connected components of the lowest layer, largest first.
std::vector<int> footprint_components(const detail::BodyBox& box) {
  std::vector<int> label(static_cast<size_t>(box.U) * box.V, 0);
  std::vector<int> sizes;
  std::vector<std::pair<int, int>> stack;
  for (int v0 = 0; v0 < box.V; ++v0)
    for (int u0 = 0; u0 < box.U; ++u0) {
      if (!box.at(u0, v0, 0) || label[u0 + box.U * v0]) continue;
      const int id = static_cast<int>(sizes.size()) + 1;
      int size = 0;
      stack.push_back({u0, v0});
      label[u0 + box.U * v0] = id;
      while (!stack.empty()) {
        const auto [u, v] = stack.back();
        stack.pop_back();
        ++size;
        const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
          const int nu = u + du[k], nv = v + dv[k];
          if (nu < 0 || nv < 0 || nu >= box.U || nv >= box.V) continue;
          if (!box.at(nu, nv, 0) || label[nu + box.U * nv]) continue;
          label[nu + box.U * nv] = id;
          stack.push_back({nu, nv});
        }
      }
      sizes.push_back(size);
    }
  std::sort(sizes.begin(), sizes.end(), std::greater<int>());
  return sizes;
}

}  // namespace

BodyPlanResult classify_body_plan(const VoxelSet& body, const BodyPlanOptions& options) {
  if (body.voxels.empty()) throw std::invalid_argument("classify_body_plan: empty body");

  BodyPlanResult res;
  BodyPlanFeatures& f = res.features;
  const detail::BodyBox upright = detail::body_box(body, 0);
  f.voxels = static_cast<int>(body.voxels.size());
  f.extent = {upright.U, upright.V, upright.Z};
  f.box_fill =
      static_cast<double>(f.voxels) / (static_cast<double>(upright.U) * upright.V * upright.Z);
  f.footprint_components = footprint_components(upright);

  // Best template of each plan over the four quarter turns (ties keep the earlier turn).
  for (int turns = 0; turns < 4; ++turns) {
    const std::array<PlanMatch, 3> m = detail::match_templates(detail::body_box(body, turns));
    for (int p = 0; p < 3; ++p)
      if (turns == 0 || m[p].score > f.matches[p].score) {
        f.matches[p] = m[p];
        f.matches[p].quarter_turns = turns;
      }
  }

  // Best plan (ties: Π, Γ, Υ) and the runner-up's score.
  int best = 0;
  for (int p = 1; p < 3; ++p)
    if (f.matches[p].score > f.matches[best].score) best = p;
  double second = 0;
  for (int p = 0; p < 3; ++p)
    if (p != best) second = std::max(second, f.matches[p].score);
  const double score = f.matches[best].score;
  res.margin = score - second;
  if (score >= options.threshold) {
    res.plan = f.matches[best].plan;
    res.confidence = score;
  } else {
    res.plan = BodyPlan::kOther;
    res.confidence = 1.0 - score;
  }
  return res;
}

}  // namespace plastivox::analysis
