// A MAP-Elites run's archive drawn from its results file (docs/evolution.md, "MAP-Elites"):
// what `plastivox archive` writes and what the study's report shows for each MAP-Elites run.
// Part of plastivox_render_files (it reads the evolver's results and simulates the elites).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/render/gallery.hpp"
#include "plastivox/render/panels.hpp"

namespace plastivox::render {

struct ArchiveRequest {
  std::string x_axis, y_axis;  // descriptor names shown; both empty: the config's first two
  int elites = 12;             // the gallery's best elites (0: no gallery, nothing simulated)
  GalleryStyle style;          // the gallery's
  FigureOptions figure;        // the map's and the QD curve's size and formats
};

// What was written and what the archive holds at the end of the run.
struct ArchiveFiles {
  std::vector<std::string> written;  // paths in order: map (svg, png), qd (svg, png), csv, gallery
  std::string map_png, qd_png, csv, gallery_png;  // each "" when not written
  int64_t cells = 0, filled = 0, evaluations = 0;
  double qd_score = 0, best_fitness = 0;
  size_t elites = 0;  // tiles in the gallery
  std::string x_name, y_name;
};

// An axis name that is not a descriptor of the run (the message names it and the run's).
class ArchiveAxisError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Writes into out_dir (created): archive.svg and archive.png (two descriptors, each cell
// coloured by its best elite's fitness over any further axes, empty cells grey), qd.svg and
// qd.png (the QD score and coverage over evaluations), archive.csv (every elite: cell, bins,
// descriptors, fitness, ids) and elites.png (the best `elites` elites, ties to the lower id,
// each simulated under the run's physics and drawn as champions' galleries are). Throws
// InputError for a results file of another algorithm, ArchiveAxisError, GallerySizeError
// (before anything is simulated or written), RenderError.
ArchiveFiles write_archive_files(const std::string& results, const std::string& out_dir,
                                 const ArchiveRequest& request);

}  // namespace plastivox::render
