// MAP-Elites (Mouret & Clune 2015, "Illuminating search spaces by mapping elites",
// arXiv:1504.04909; docs/evolution.md, "MAP-Elites"): what a robot and its life give the
// archive's descriptors, and which cell of the grid a set of values falls in. The archive
// itself and the generation are the evolver's (Evolver::step_map_elites).
#pragma once

#include <cstdint>
#include <vector>

#include "plastivox/evo/config.hpp"
#include "plastivox/evo/phenotype.hpp"

namespace plastivox {
struct Model;
struct State;
}  // namespace plastivox

namespace plastivox::evo {

// The most cells an archive may have (the grid is held whole in results files' cell indices,
// and every cell's elite in memory).
constexpr int64_t kMaxArchiveCells = 1000000;

// What a life gives the descriptors. Measured by the evaluator from the states it steps
// through (DescriptorWatch), never from a State row of its own, so no life and no golden hash
// moves.
struct DescriptorMeasures {
  bool measured = false;  // false: an outside fitness gave a number alone
  // Mean over the samples of the share of the robot's voxels touching the ground (a voxel's
  // bottom face, half its actuated size below its centre, tilt ignored, below the ground:
  // HeightField::penetration > 0, the floor contact's own test); 0 without a floor. In [0, 1].
  double floor_contact = 0;
  // Mean over the samples of the robot's centre of mass above the ground under it, voxel
  // lengths.
  double com_height = 0;
  // Mean |E/E0 - 1| over the robot's voxels at the end of life (SimResult::
  // stiffness_change_abs_mean); 0 when nothing develops.
  double development = 0;
  bool operator==(const DescriptorMeasures&) const = default;
};

// The gait's samples are taken every kLifeSampleInterval of simulated time: the first state
// at or past t = 0, 0.01, 0.02, ... s (as recordings take frames), so their cost is a few
// hundred loops over the voxels in a life of tens of thousands of steps.
constexpr double kLifeSampleInterval = 0.01;  // s

// Watches a life while it is stepped: see() before the first step and after every step.
class DescriptorWatch {
 public:
  explicit DescriptorWatch(const Model& model) : model_(model) {}
  void see(const State& s);
  // development: the life's SimResult::stiffness_change_abs_mean.
  DescriptorMeasures finish(double development) const;

 private:
  const Model& model_;
  double next_ = 0;  // s: the next sample's time
  int64_t samples_ = 0;
  double contact_sum_ = 0, height_sum_ = 0;
};

// Whether a descriptor is the life's (development, floor_contact, com_height) or the body's.
bool from_life(Descriptor d);
bool needs_life(const MapElitesSettings& s);

// Each axis's value for a valid body, axis order, the life's descriptors NaN; life_descriptors
// then fills those in from the life's measures.
std::vector<double> body_descriptors(const MapElitesSettings& s, const Phenotype& p);
void life_descriptors(const MapElitesSettings& s, const DescriptorMeasures& life,
                      std::vector<double>& values);

// The cell of a set of values: axis k's bin is floor((v - lo) / (hi - lo) * bins), values
// outside [lo, hi] in the end bins; cells are numbered row-major, the first axis slowest.
// -1 when a value is NaN.
int64_t cell_of(const MapElitesSettings& s, const std::vector<double>& values);
// Each axis's bin of a cell (row-major, as cell_of numbers them).
std::vector<int> bins_of(const MapElitesSettings& s, int64_t cell);

}  // namespace plastivox::evo
