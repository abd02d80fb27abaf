// The results file of a run: HDF5, layout in docs/results-format.md (library
// plastivox_evo_h5; the only part of the evolver that knows HDF5).
//
// The file is also the checkpoint: it holds the whole RunState. It is always replaced
// atomically (written to "<path>.tmp", fsync'ed, renamed over <path>, directory fsync'ed),
// so a reader or a resumed run only ever sees a complete checkpoint, whenever the writer
// was killed. Not thread-safe (HDF5's serial build): call from one thread.
#pragma once

#include <stdexcept>
#include <string>

#include "plastivox/base/error.hpp"
#include "plastivox/evo/run_state.hpp"

namespace plastivox::evo {

constexpr int kResultsFormatVersion = 1;

// Any problem with a results file; what() is one line naming the file and the object.
class ResultsError : public Error {
 public:
  using Error::Error;
};

// Where and how a file was produced (root attributes; not part of the content digest).
struct Provenance {
  std::string plastivox_version;  // PROJECT_VERSION of the writer
  std::string git_commit;         // commit the writer was configured at
  std::string compiler;           // id and version
  std::string compiler_flags;     // C++ flags and compile options of the build
  std::string build_type;
  std::string date_created;  // UTC, ISO 8601; kept when a run is resumed
  std::string date_updated;  // UTC, ISO 8601, of this checkpoint
  std::string host;          // host name of the writer
  int64_t threads = 0;       // evaluation threads of the writer
  double wall_seconds = 0;   // summed wall time of all sessions, s
};

// Provenance of this build and machine, now (date_created = date_updated = now).
Provenance current_provenance(int threads);

// Writes the whole state atomically; throws ResultsError.
void write_results(const std::string& path, const RunState& state, const Provenance& prov);

struct ResultsFile {
  RunState state;  // population phenotypes are not filled (Evolver re-expresses them)
  Provenance provenance;
  std::string content_digest;  // as stored, and verified equal to the recomputed one
};

// Reads and checks a results file: HDF5 signature, format and version, every dataset's
// type and shape, network invariants, and the stored digests. Throws ResultsError with
// one line for a missing, foreign, truncated or corrupt file.
ResultsFile read_results(const std::string& path);

}  // namespace plastivox::evo
