// Body-plan classification (docs/method.md §8, "Body plans"): the paper names three recurring
// body plans by eye — Π (wide front and back legs under a bridge), Γ (legs meeting at a right
// angle) and Υ (a mainly cylindrical leg joined at right angles to the centre of a roughly
// 10x10 vertical plate) — and counts them per treatment. This is a deterministic geometric
// rule that does the same: template matching on the body's bounding box.
//
// The rule. The body stands as it is in its lattice (z up). For each of the 4 quarter turns
// about z, its bounding box (extent U along x = the "travel" axis u, V along y, Z along z) is
// compared with idealised templates, each a set T of cells of that box with a hole H (the rest
// of the box):
//   Π  legs {u < a1} and {u >= U - a2} over the full width and height, bridge {z >= Z - b};
//      the gap under the bridge must be >= 2 cells wide and >= 2 high.
//   Γ  two plates meeting at an edge, each from one end of the other: a wall {u < a} with
//      either a floor plate {z < b} (side view "L"), a top bar {z >= Z - b} (side view "Γ"),
//      or a second wall {v < b} (plan view "L"); each limb leaves >= 2 cells of hole.
//   Υ  a wall {u < a} (a <= max(1, U / 3), full width and height) and a rod along u from the
//      wall to the far end, with a round cross-section of radius r (1 .. min(V, Z) / 3, in
//      half-cell steps) centred within the middle half of the wall.
// A template's score is min(fill, empty, inside): fill = the fraction of T's cells that hold a
// voxel, empty = the fraction of H's cells that do not, inside = the fraction of the body's
// voxels that lie in T. (empty alone would forgive a misplaced limb when the hole is large;
// inside alone would forgive a solid block, which fills any template.) A plan's score is its best
// template's (over all parameters and the 4 turns; ties keep the first in enumeration order). The
// label is the best-scoring plan (ties: Π, Γ, Υ) if its score reaches the threshold, else "other".
// confidence = the best plan's score for a labelled body, 1 - that score for "other";
// margin = best minus second-best plan score. Everything is in lattice units; the rule is
// invariant under quarter turns about z (a turned copy gets the same label and scores) and
// under translation. The threshold is a judgement, not calibrated on the paper's champions.
// Functions are pure and thread-safe.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "plastivox/analysis/voxel_set.hpp"

namespace plastivox::analysis {

enum class BodyPlan { kPi, kGamma, kUpsilon, kOther };
const char* to_string(BodyPlan p);  // "Pi", "Gamma", "Upsilon", "other"
const char* symbol(BodyPlan p);     // "Π", "Γ", "Υ", "other" (UTF-8)

// The best template of one plan.
struct PlanMatch {
  BodyPlan plan = BodyPlan::kOther;
  double score = 0;        // min(fill, empty, inside), in [0, 1]
  double fill = 0;         // fraction of template cells filled
  double empty = 0;        // fraction of hole cells empty
  double inside = 0;       // fraction of the body's voxels that lie in the template
  int quarter_turns = 0;   // turns of +90 deg about z applied to the body before matching
  std::string parameters;  // the template's variant and sizes, e.g. "legs 2+2, bridge 3"
};

struct BodyPlanFeatures {
  int voxels = 0;
  Voxel extent = {0, 0, 0};  // bounding-box size along x, y, z, lattice units
  double box_fill = 0;       // voxels / bounding-box volume
  // Floor contact: sizes of the 4-connected components of the lowest layer, largest first.
  std::vector<int> footprint_components;
  std::array<PlanMatch, 3> matches;  // best Π, Γ, Υ templates, in that order
};

struct BodyPlanResult {
  BodyPlan plan = BodyPlan::kOther;
  double confidence = 0;  // see the rule above, in [0, 1]
  double margin = 0;      // best minus second-best plan score
  BodyPlanFeatures features;
};

struct BodyPlanOptions {
  double threshold = 0.75;  // minimum plan score for a label other than "other"
};

// Throws std::invalid_argument for an empty set.
BodyPlanResult classify_body_plan(const VoxelSet& body, const BodyPlanOptions& options = {});

}  // namespace plastivox::analysis
