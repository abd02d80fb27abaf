// The one error hierarchy. Every what() is one line that names the file and the field (or
// the option) at fault, so the CLI can print it as it is and exit non-zero.
//
//   Error                    anything plastivox reports
//   ├─ InputError            a bad input file or field (exit 1)
//   │  └─ VxaError           ... in a .vxa file, naming the tag
//   ├─ UsageError            a bad command-line value (exit 2)
//   ├─ ResultsError          a results file that cannot be read or written (evo/)
//   │  └─ RunRefused         a run that will not start or resume over an existing file
//   ├─ RenderError           drawing, fonts, assets, image output (render/)
//   │  └─ GallerySizeError
//   ├─ VideoError            encoding and decoding (render/)
//   └─ StatsError            a malformed stats.json (render/)
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

}  // namespace plastivox
