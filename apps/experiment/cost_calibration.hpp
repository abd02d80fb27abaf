// The cost model's calibration: every constant fitted to measurements, with where and how it
// was measured. The rendering constants price the stages around the simulations
// (rendering_seconds, schedule_prediction.cpp); the disk constants price what a study writes
// (estimate_disk, disk_estimate.cpp). Refit them here, with their provenance, when the
// outputs or the drawing change.
#pragma once

#include <algorithm>
#include <cmath>

namespace plastivox::experiment::calibration {

// ---- Rendering: the stages around the simulations ----
//
// Seconds measured on the machine the constants were fitted on (2-core AMD EPYC, idle,
// 2026-12-04; the calibration read 19.7-21.4 M voxel-steps/s there), from the stage times of
// the tiny and default presets at 1 and 2 threads (docs/experiment.md, "Measured"). Drawing
// is priced at this machine's measured speed against that one: llvmpipe draws on the CPU.
inline constexpr double kReferenceSpeed = 20e6;  // voxel-steps/s of the calibration there
inline constexpr double kStartSeconds = 0.3;     // start-up and this calibration, before any stage
// A run's generation recorded, its checkpoint included.
inline constexpr double kGenerationSeconds = 0.03;
inline constexpr int kFigureStems = 8;      // figures drawn: evolution, panels A-F, figure 5
inline constexpr double kDrawStart = 0.15;  // the first OpenGL context (llvmpipe's shaders)
inline constexpr double kFigureSecondsPerMP = 0.37;  // a figure: drawn, PNG written (one thread)
// On one drawing thread: a gallery (4x multisampled) and a video frame (drawn and encoded), a
// fixed part and one per megapixel. The bodies' size mattered less than the pixels.
inline constexpr double kGallerySeconds = 0.13, kGallerySecondsPerMP = 0.44;
inline constexpr double kFrameSeconds = 0.030, kFrameSecondsPerMP = 0.076;
// llvmpipe's speed-up with t rasteriser threads: 1.55 measured at 2; assumed to grow at that
// rate up to 4 and no further.
inline double raster_speedup(int threads) {
  return 1 + 0.55 * (std::clamp(threads, 1, 4) - 1);
}

// ---- Disk ----
//
// Bytes measured on real outputs (uncompressed HDF5, PNG, H.264; docs/experiment.md, "Disk
// space"), fitted per item: the tiny preset (6 runs of 2 generations, 1.5 MB in all) and a
// 200-generation evolution of population 6 (1.39 MB, 74 champions, 1406 individuals). A
// typical size, not a bound: champions and image content vary from run to run.
inline constexpr double kRunFixed = 40e3;       // a results file's headers, attributes, config
inline constexpr double kPerBirth = 70;         // its /individuals row and cache entry
inline constexpr double kPerGeneration = 35;    // the /generations columns of one generation...
inline constexpr double kPerSurvivor = 30;      // ...and of each survivor in it
inline constexpr double kPerChampion = 14e3;    // genomes, groups and dataset headers
inline constexpr double kPerChampionSite = 33;  // phenotype: present u8 + four f64 per site
inline constexpr double kPerCheckpointGenome = 3e3;    // the stacked population in /checkpoint
inline constexpr double kAnalysisFixed = 120e3;        // analysis.h5 and report headers, CSS, stats
inline constexpr double kPerChampionAnalysis = 12e3;   // a champion's rows in every table
inline constexpr double kFigureBytesPerPixel = 0.085;  // PNG figures (lines on white)
inline constexpr double kGalleryBytesPerPixel = 0.29;  // PNG galleries (shaded bodies)
inline constexpr double kSvgBytes = 6e3;               // one vector figure
inline constexpr double kVideoBytesPerPixelFrame = 0.02;  // H.264 of a body on a plain floor
// The 3-D viewer (docs/rendering.md): three.js, OrbitControls, the viewer and colour maps
// inlined in report.html once; per champion a life of 60 + 20F + n (8 + 13F) packed bytes
// (F frames at render::kViewerFps per simulated second, n voxels, about half the lattice for
// evolved bodies), a third more as base64, and its colour scales.
inline constexpr double kViewerScripts = 900e3;
inline constexpr double kLifeMeta = 2.5e3;
inline constexpr double kBodyFill = 0.5;

// New champions a run records: 3 in 2 generations, 74 in 200 (short, noisy lives); the
// rate falls as improvements get rarer.
inline double champions_per_run(int generations) {
  const double g = generations;
  return std::min(g + 1, 1 + std::pow(g, 0.8));
}

}  // namespace plastivox::experiment::calibration
