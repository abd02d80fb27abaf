// The one error hierarchy. Every what() is one line that names the file and the field (or
// the option) at fault, so the CLI can print it as it is and exit non-zero. Each class lives
// with what throws it; the four every layer throws are defined here:
//
//   Error                    anything plastivox reports                 (here)
//   ├─ InputError            a bad input file or field (exit 1)         (here)
//   │  └─ VxaError           ... in a .vxa file, naming the tag         (plastivox/io/vxa.hpp)
//   ├─ UsageError            a bad command-line value (exit 2)          (here)
//   ├─ ResultsError          a result file that cannot be read/written  (here)
//   │  └─ RunRefused         a run that will not start or resume        (plastivox/evo/run.hpp)
//   ├─ RenderError           drawing, fonts, assets, image output (plastivox/render/error.hpp) │ └─
//   GallerySizeError                                              (plastivox/render/gallery.hpp) ├─
//   VideoError            encoding and decoding (plastivox/render/video_writer.hpp) └─ StatsError
//   a malformed stats.json                     (plastivox/render/panels.hpp)
//
// Runtime faults of a simulation (a life that goes unstable) are statuses, not exceptions.
#pragma once

#include <stdexcept>
#include <string>

namespace plastivox {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

class InputError : public Error {
 public:
  using Error::Error;
};

class UsageError : public Error {
 public:
  using Error::Error;
};

// A file of results (a results file, a recorded life, a study's analysis.h5) that cannot be
// read or written; what() is one line naming the file and the object.
class ResultsError : public Error {
 public:
  using Error::Error;
};

}  // namespace plastivox
