// Lives read from files, and the renderer's commands that take file names (library
// plastivox_render_files, over plastivox_render): a robot file (.json plastivox robot or .vxa),
// simulated under its own physics; an evolution results file (.h5), whose champion is
// simulated again under the run's physics and treatment; or a recorded life (.h5 written by
// plastivox simulate --record), drawn as recorded. The drawing itself (plastivox_render)
// takes LifeSource and frames and knows nothing of these files.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "plastivox/render/gallery.hpp"
#include "plastivox/render/life.hpp"
#include "plastivox/render/render_life.hpp"
#include "plastivox/render/viewer.hpp"

namespace plastivox::render {

// A life simulated from `robot` under `physics`: compiled here (with the program's limits,
// limits_from_environment()), its frames simulated when asked for. Throws InputError naming
// `path` for a robot or physics the engine refuses.
LifeSource simulated_life_source(const std::string& path, RobotDef robot, PhysicsDef physics,
                                 const std::string& label);

// Reads by extension: .json, .vxa, .h5 (a results file, generation -1: the last one done;
// or a recorded life). Throws InputError / VxaError / ResultsError (all
// std::runtime_error, one line naming the file).
LifeSource load_life_source(const std::string& path, int generation = -1);

// The source of a recorded-life file (plastivox/io/life_file.hpp): its robot, physics and
// frames.
LifeSource recorded_life_source(const std::string& path);

// Renders the frame at simulated time `time` (s) of the robot or results file `source` to
// a PNG at `out` (written atomically), the camera framing it as life_cameras does.
void render_frame_file(const std::string& source, double time, const FrameStyle& style,
                       const std::string& out, const LogFn& log = {});

// render_video() of the life in the file `source`.
VideoSummary render_video_file(const std::string& source, const FrameStyle& style,
                               const VideoJob& job, const std::string& out, const LogFn& log = {});

// Renders the gallery to a PNG at `out` (atomically). Inputs are results files (.h5; robot
// files are accepted too). `log` receives one line per item. Throws on the first bad input,
// leaving no file.
GalleryLayout render_gallery_file(const std::vector<std::string>& inputs, const GalleryStyle& style,
                                  const std::string& out, const LogFn& log = {});

// show_life() of the life in `file` (generation of a results file: -1 the last).
ShownLife show_life(const std::string& file, int generation, double fps,
                    const std::function<void(const std::string&)>& log = {});

// A champion a report replays: its id (the run label, also the script's name), its results
// file and generation (-1: the last).
struct ReportChampion {
  std::string id;
  std::string file;
  int generation = -1;
};

// Writes each champion's life to `dir`/lives/<id>.js (simulated at `fps` frames per
// simulated second, on up to `threads` threads), removes other lives there, and returns the
// links in the sources' order. A life that does not finish is left out, with a line to `log`.
std::vector<ViewerLink> write_report_lives(const std::vector<ReportChampion>& sources,
                                           const std::string& dir, double fps, int threads,
                                           const std::function<void(const std::string&)>& log);

}  // namespace plastivox::render
