// The results file of a run: HDF5, layout in docs/results-format.md (writes go through
// plastivox_io's HDF5 helpers).
//
// The file is also the checkpoint: it holds the whole RunState. It is always replaced
// atomically (written to "<path>.tmp", fsync'ed, renamed over <path>, directory fsync'ed),
// so a reader or a resumed run only ever sees a complete checkpoint, whenever the writer
// was killed. Not thread-safe (HDF5's serial build): call from one thread.
#pragma once

#include <stdexcept>
#include <string>

#include "plastivox/base/error.hpp"  // ResultsError
#include "plastivox/evo/run_state.hpp"
#include "plastivox/io/provenance.hpp"

namespace plastivox::evo {

constexpr int kResultsFormatVersion = 1;

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
