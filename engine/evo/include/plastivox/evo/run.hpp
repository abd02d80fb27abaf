// Running an evolution to completion with checkpoints and resume (library plastivox_evo).
//
// run_evolution(config, out) is what `plastivox evolve --config F --out R.h5` does:
//   - R.h5 absent: start a new run;
//   - R.h5 present and written by the same config identity (EvolveConfig::identity_json,
//     and the same resolved physics): continue from its checkpoint; the end result is
//     bit-identical to an uninterrupted run;
//   - R.h5 present but from another config, or not a readable results file: refuse
//     (ResultsError / InputError) and leave it untouched;
//   - R.h5 already finished: report so and change nothing.
// A checkpoint is written every config.checkpoint_every generations and at the end.
// While it runs, "<out>.lock" is flock()ed: a second evolve on the same file is refused.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "plastivox/evo/evolver.hpp"
#include "plastivox/evo/results_file.hpp"

namespace plastivox::evo {

class EvaluationPool;

struct RunProgress {
  GenerationStats stats;       // of the generation just done
  int generations_done = 0;    // after it
  int generations_total = 0;   // planned
  double session_seconds = 0;  // wall time of this session so far
  double eta_seconds = 0;      // remaining, from this session's mean generation time
  bool checkpointed = false;   // a checkpoint was written after this generation
  double checkpoint_seconds = 0;
};

// A group of processes running one evolution together (implemented over MPI in
// mpi_cluster.hpp). Every rank runs the same deterministic evolver in lockstep; only the
// simulations are divided (Simulations::run is collective). Rank 0 alone reads the results
// file first, decides (new run, resume, finished, refuse), writes checkpoints and reports
// progress; the other ranks follow its decision and read the same file when resuming (so
// it must be on a file system every rank sees).
class Cluster : public Simulations {
 public:
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual void broadcast(std::string& text) = 0;  // collective: rank 0's text to every rank
  virtual void barrier() = 0;                     // collective: wait for every rank
  // The evaluation pool over every rank (run_evolutions under mpirun). Rank 0 alone drives
  // the runs; its main thread calls serve(), which hands simulations queued in `pool` to
  // the other ranks (as many at a time as each has threads) and completes them with the
  // results, until finished() is true and none is out, then releases the ranks. Every
  // other rank calls work() meanwhile: it simulates what rank 0 sends on `threads` threads.
  virtual void serve(EvaluationPool& pool, const std::function<bool()>& finished) = 0;
  virtual void work(int threads) = 0;
};

// A refusal decided by rank 0 and raised on every rank alike (so no rank has to abort the
// others): unreadable results file, different configuration.
class RunRefused : public ResultsError {
 public:
  using ResultsError::ResultsError;
};

struct RunOptions {
  Cluster* cluster = nullptr;  // nullptr: a single process
  // A backend shared with other runs (EvaluationPool, eval_pool.hpp), used when there is no
  // cluster; the run then makes and expresses candidates on the calling thread alone.
  Simulations* simulations = nullptr;
  int threads = -1;     // evaluation threads; -1: the config's; 0: all cores
  int stop_after = -1;  // testing hook: stop once generations_done reaches this (checkpointed)
  // Polled after every generation: when it reads true the run checkpoints and stops
  // (outcome kStopped, resumable). Set from a SIGINT handler for a clean Ctrl-C. Under a
  // cluster rank 0's flag decides for every rank, so all stop after the same generation.
  const std::atomic<bool>* stop_requested = nullptr;
  // What scores the lives, recorded in the results file's provenance (fitness_function):
  // empty for the engine's own; a name for an outside one, given through `simulations`
  // (Python's fitness functions and ask/tell). A run is resumed only with the same.
  std::string fitness_function;
  std::function<void(const RunProgress&)> on_generation;  // called after every generation
  std::function<void(const std::string&)> on_message;     // "resuming from generation 12"...
};

enum class RunOutcome {
  kFinished,         // this session completed the run
  kAlreadyFinished,  // the results file was complete; nothing was changed
  kStopped,          // stopped by stop_after or stop_requested; resumable
};

struct RunReport {
  RunOutcome outcome = RunOutcome::kFinished;
  int resumed_from = -1;  // generations_done found in the file; -1 for a new run
  int generations_done = -1;
  std::string content_digest;
  int threads = 0;  // threads used
};

RunReport run_evolution(const EvolveConfig& config, const std::string& out_path,
                        const RunOptions& options);

// Several evolutions at once, one results file each (what `plastivox experiment` and
// `plastivox evolve` with several configs do in one process): every run drives its own
// evolver on its own thread, and all their candidates share one EvaluationPool of
// `threads` workers (-1: the first config's threads; 0: all cores). Each run behaves as
// run_evolution() alone (new, resume, finished, refuse; checkpoints; its own lock) and
// gives the same bits. stop_requested stops every run after its generation in flight
// (checkpointed); so does the first run that fails, whose exception (lowest run index)
// is rethrown once every run has stopped. The callbacks are called one at a time, with
// the run's index. Output paths must differ. With a cluster, rank 0 alone runs the drivers
// (decides, writes files, reports) and every rank's threads serve the queue; the other
// ranks return no reports.
struct RunSpec {
  EvolveConfig config;
  std::string out_path;
};
struct ManyRunOptions {
  Cluster* cluster = nullptr;  // under mpirun: rank 0 drives, every rank simulates
  int threads = -1;
  const std::atomic<bool>* stop_requested = nullptr;
  std::function<void(size_t run, const RunProgress&)> on_generation;
  std::function<void(size_t run, const std::string&)> on_message;
};
std::vector<RunReport> run_evolutions(const std::vector<RunSpec>& runs,
                                      const ManyRunOptions& options);

// Empty when a and b may share a results file; otherwise a one-line description of the
// first difference ("seed: 1 in the file, 2 now").
std::string config_difference(const EvolveConfig& file, const EvolveConfig& now);

}  // namespace plastivox::evo
