// plastivox hausdorff: the Hausdorff distance between the filled-voxel sets of two robot files
// (analysis/include/plastivox/analysis/hausdorff.hpp), minimised over the chosen placements.
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/io/robot_io.hpp"

namespace plastivox::cli {
namespace {

// The geometry of a robot file: .vxa in the authors' dialect, anything else the project's JSON.
// Only which sites are filled matters here, so VXA warnings about physics are not shown.
analysis::VoxelSet read_geometry(const std::string& path) {
  analysis::VoxelSet set = analysis::voxel_set(load_robot(path).robot);
  if (set.voxels.empty()) throw std::runtime_error(path + ": the robot has no voxels");
  return set;
}

}  // namespace

int cmd_hausdorff(const Args& in) {
  Args args = in;
  const bool as_json = take_flag(args, "--json");
  const std::string rotations = take_option(args, "--rotations", "paper");
  const std::string translation = take_option(args, "--translation", "");
  reject_unknown_options(args);
  if (args.size() != 2) throw UsageError{"expected two robot files, A and B"};

  analysis::HausdorffOptions options;
  try {
    options.rotations = analysis::parse_rotation_search(rotations);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--rotations: ") + e.what()};
  }
  // The full rotation search aligns translations too unless told otherwise.
  options.translation = options.rotations == analysis::RotationSearch::kAll
                            ? analysis::TranslationSearch::kInteger
                            : analysis::TranslationSearch::kNone;
  if (translation == "none") {
    options.translation = analysis::TranslationSearch::kNone;
  } else if (translation == "integer") {
    options.translation = analysis::TranslationSearch::kInteger;
  } else if (!translation.empty()) {
    throw UsageError{"--translation expects none or integer, got '" + translation + "'"};
  }

  const analysis::VoxelSet a = read_geometry(args[0]);
  const analysis::VoxelSet b = read_geometry(args[1]);
  const analysis::HausdorffResult r = analysis::hausdorff(a, b, options);

  if (as_json) {
    nlohmann::json j;
    j["distance"] = r.distance;
    j["distance_squared"] = r.distance2;
    j["units"] = "voxel lengths";
    j["a"] = args[0];
    j["b"] = args[1];
    j["voxels_a"] = a.voxels.size();
    j["voxels_b"] = b.voxels.size();
    j["rotations"] = to_string(r.rotations);
    j["translation_search"] = to_string(r.translation_search);
    j["rotation"] = {{"index", r.rotation_index},
                     {"of", analysis::rotation_set(r.rotations).size()},
                     {"image", r.rotation.name},
                     {"matrix", r.rotation.m}};
    j["translation"] = r.translation;
    std::printf("%s\n", j.dump(1).c_str());
  } else {
    std::printf(
        "d_H = %.6g voxel lengths (rotations %s: best %d of %zu, B -> %s; translation "
        "%s: [%d, %d, %d])\n",
        r.distance, to_string(r.rotations), r.rotation_index,
        analysis::rotation_set(r.rotations).size(), r.rotation.name.c_str(),
        to_string(r.translation_search), r.translation[0], r.translation[1], r.translation[2]);
  }
  return 0;
}

}  // namespace plastivox::cli
