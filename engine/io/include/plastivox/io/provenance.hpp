// Provenance: where and how a result file was made (results files, recorded lives, a study's
// analysis.h5 and summaries carry it).
#pragma once

#include <cstdint>
#include <string>

namespace plastivox {

// Where and how a file was produced (root attributes; not part of the content digest).
struct Provenance {
  std::string plastivox_version;  // PROJECT_VERSION of the writer
  std::string git_commit;         // commit the writer was built at (build_git_commit())
  std::string compiler;           // id and version
  std::string compiler_flags;     // C++ flags and compile options of the build
  std::string build_type;
  std::string date_created;  // UTC, ISO 8601; kept when a run is resumed
  std::string date_updated;  // UTC, ISO 8601, of this checkpoint
  std::string host;          // host name of the writer
  int64_t threads = 0;       // evaluation threads of the writer
  double wall_seconds = 0;   // summed wall time of all sessions, s
  // What scored the lives of an evolution: "built-in" (the engine's, the default) or
  // "python: <name>" (a fitness function or an ask/tell loop from Python). Empty in files
  // written before 2026-12-05 and in files that are not evolutions: built-in.
  std::string fitness_function;
};

// The commit of the sources this binary was built from, 12 hex digits, with "-dirty" when
// tracked files differed from it, or "unknown" when built outside a git work tree. Taken at
// every build, not when CMake configured the build folder (until 2026-12-07 it was the
// configure-time commit, which a later pull and build kept).
const char* build_git_commit();

// Calls f(name, member) for every field of p, in the order above; the names are the HDF5
// root attributes (docs/results-format.md), the JSON keys of `inspect --json` and the Python
// dict's keys. P is Provenance or const Provenance. Every reader, writer and printer of
// provenance goes through this, so a new field is added in one line.
template <class P, class F>
void for_each_field(P& p, F&& f) {
  f("plastivox_version", p.plastivox_version);
  f("git_commit", p.git_commit);
  f("compiler", p.compiler);
  f("compiler_flags", p.compiler_flags);
  f("build_type", p.build_type);
  f("date_created", p.date_created);
  f("date_updated", p.date_updated);
  f("host", p.host);
  f("threads", p.threads);
  f("wall_seconds", p.wall_seconds);
  f("fitness_function", p.fitness_function);
}

// Provenance of this build and machine, now (date_created = date_updated = now).
Provenance current_provenance(int threads);

}  // namespace plastivox
