// What a study writes on disk, priced by the calibration in cost_calibration.hpp, and the
// check that refuses to start a study the file system has no room for (cost_estimate.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include <sys/statvfs.h>

#include "cost_calibration.hpp"
#include "cost_estimate.hpp"
#include "plastivox/base/error.hpp"     // InputError
#include "plastivox/render/viewer.hpp"  // kViewerFps

namespace plastivox::experiment {
namespace {

uint64_t folder_bytes(const std::string& dir) {
  std::error_code ec;
  uint64_t sum = 0;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code size_ec;
    if (it->is_regular_file(size_ec)) sum += it->file_size(size_ec);
  }
  return sum;
}

}  // namespace

DiskEstimate estimate_disk(const ExperimentConfig& config, bool viewer) {
  using namespace calibration;
  const evo::EvolveConfig& e = config.evolution;
  const double p = e.population, g = e.generations, runs = config.runs();
  const double sites = static_cast<double>(e.nx) * e.ny * e.nz;
  const double births = static_cast<double>(config.lives_per_run());
  const bool map_elites = e.algorithm == evo::Algorithm::kMapElites;
  // MAP-Elites keeps its archive too: at most a genome a cell, and never more than it made.
  const double elites =
      map_elites ? std::min(births, static_cast<double>(e.map_elites.cells())) : 0;
  const double run_file =
      kRunFixed + births * kPerBirth + g * (kPerGeneration + p * kPerSurvivor) +
      champions_per_run(e.generations) * (kPerChampion + kPerChampionSite * sites) +
      (p + elites) * kPerCheckpointGenome;
  DiskEstimate d;
  d.evolution = static_cast<uint64_t>(runs * run_file);
  const double draws = config.analysis.robustness_draws;
  d.analysis = static_cast<uint64_t>(kAnalysisFixed + runs * (kPerChampionAnalysis + 16 * draws) +
                                     runs * runs * 16);
  const RenderSettings& r = config.rendering;
  double figures = 0, galleries = 0, video = 0;
  if (r.figures)
    figures = kFigureStems * (r.figure_width * r.figure_height * kFigureBytesPerPixel + kSvgBytes);
  if (r.galleries)
    galleries =
        config.treatments.size() * r.gallery_width * r.gallery_height * kGalleryBytesPerPixel;
  if (r.video)
    video = r.video_width * r.video_height * kVideoBytesPerPixelFrame * r.video_fps *
            e.physics.duration;
  // A MAP-Elites run's archive (archives/<run>/): its map and QD curve as figures, its table
  // (about 100 B an elite) and its elites' gallery.
  double archives = 0;
  if (map_elites && r.figures)
    archives =
        runs *
        (2 * (r.figure_width * r.figure_height * kFigureBytesPerPixel + kSvgBytes) + 100 * elites +
         (r.galleries ? r.gallery_width * r.gallery_height * kGalleryBytesPerPixel : 0));
  d.rendering = static_cast<uint64_t>(figures + galleries + video + archives);
  if (viewer) {
    const double frames = std::floor(e.physics.duration * render::kViewerFps) + 1;
    const double voxels = kBodyFill * sites;
    // A champion's life is simulated for the viewer with its actuation signal: one byte more.
    const double per_voxel_frame = render::kPackedBytesPerVoxelFrame + 1;
    const double life =
        4.0 / 3.0 * (60 + 20 * frames + voxels * (8 + per_voxel_frame * frames)) + kLifeMeta;
    d.viewer = static_cast<uint64_t>(kViewerScripts + runs * life);
  }
  d.largest_checkpoint = static_cast<uint64_t>(run_file);
  d.largest_file = static_cast<uint64_t>(
      std::max({run_file, video, d.analysis / 2.0 + (viewer ? kViewerScripts : 0)}));
  return d;
}

void check_free_space(const ExperimentConfig& config, const std::string& dir, bool viewer) {
  const char* skip = std::getenv("PLASTIVOX_SKIP_DISK_CHECK");
  if (skip && *skip) return;  // the estimate is typical, not a bound: the user knows better
  struct statvfs v {};
  if (statvfs(dir.c_str(), &v) != 0) return;  // unknown: the writes will say
  const uint64_t free_bytes = static_cast<uint64_t>(v.f_bavail) * v.f_frsize;
  const DiskEstimate d = estimate_disk(config, viewer);
  const uint64_t have = folder_bytes(dir);
  // A folder that already holds the estimate's bytes has nothing more to write but rewrites;
  // those are atomic, so a full disk fails them cleanly with nothing lost.
  if (have >= d.total()) return;
  const uint64_t need = d.total() - have + (have > 0 ? d.largest_file : d.largest_checkpoint);
  if (free_bytes < need)
    throw InputError(dir + ": the study needs about " + human_size(need) + " more on disk (" +
                     human_size(d.total()) + " in all) but only " + human_size(free_bytes) +
                     " is free there; free some space, use another --out folder, or set "
                     "PLASTIVOX_SKIP_DISK_CHECK=1");
}

std::string human_size(uint64_t b) {
  char buf[32];
  if (b >= uint64_t{1} << 30)
    std::snprintf(buf, sizeof buf, "%.1f GB", b / 1073741824.0);
  else if (b >= 1 << 20)
    std::snprintf(buf, sizeof buf, "%.1f MB", b / 1048576.0);
  else if (b >= 1 << 10)
    std::snprintf(buf, sizeof buf, "%.1f kB", b / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%ju B", static_cast<uintmax_t>(b));
  return buf;
}

}  // namespace plastivox::experiment
