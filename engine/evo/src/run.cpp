// The evolve driver: new run or resume, generations, checkpoints, progress.
#include "plastivox/evo/run.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "plastivox/base/parallel.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/task.hpp"

namespace plastivox::evo {
namespace {

using nlohmann::json;

// An exclusive lock on "<out>.lock" for the life of a run, so two processes never write
// one results file. flock() locks die with their process, so a kill -9 never leaves a
// held lock behind (only the empty file, taken over by the next run). A run that ends removes
// the file while it still holds the lock; so a process that opened it just before and locks it
// just after holds a lock on a file no longer named "<out>.lock", and must check that the name
// still leads to the file it locked (else it tries again), or two runs could each hold a lock.
class RunLock {
 public:
  explicit RunLock(const std::string& out) : path_(out + ".lock") {
    try {  // refuse a device or folder as the results file before the lock is created
      check_output_path(out);
    } catch (const InputError& e) {
      throw ResultsError(e.what());
    }
    while (!take(out)) {
    }
    if (fd_ >= 0) remove_stale_temporaries(out);  // a kill during a checkpoint leaves these
  }
  ~RunLock() {
    if (fd_ < 0) return;
    ::unlink(path_.c_str());  // before the lock is released: see take()
    ::close(fd_);
  }
  // Why no lock is held ("" when one is): the results file can be read but not written.
  const std::string& unwritable() const { return unwritable_; }
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  // One try: true when the lock is held (or the run needs none), false when the file locked
  // was removed meanwhile by the run that held it.
  bool take(const std::string& out) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      const std::string why =
          out + ": cannot create lock file " + path_ + ": " + std::strerror(errno);
      // A results file on a read-only mount (or in a folder this user cannot write) may
      // still be a finished run, which needs no lock: the caller decides from the file.
      if ((errno == EROFS || errno == EACCES) && std::filesystem::exists(out)) {
        unwritable_ = why;
        return true;
      }
      throw ResultsError(why);
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
      throw ResultsError(out + ": another plastivox evolve is running on this file (" + path_ +
                         " is locked)");
    }
    struct stat held {};
    struct stat named {};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino)
      return true;
    ::close(fd_);
    fd_ = -1;
    return false;
  }

  std::string path_;
  int fd_ = -1;
  std::string unwritable_;
};

}  // namespace

std::string config_difference(const EvolveConfig& file, const EvolveConfig& now) {
  if (file.task != now.task)  // said plainly: its fitness means another thing
    return std::string("task: ") + to_string(file.task) + " in the file, " + to_string(now.task) +
           " now";
  const std::string d = first_difference(json::parse(file.identity_json()),
                                         json::parse(now.identity_json()), "in the file", "now");
  if (!d.empty()) return d;
  return first_difference(json::parse(resolved_physics_json(file.physics)),
                          json::parse(resolved_physics_json(now.physics)), "in the file", "now",
                          "resolved physics");
}

RunReport run_evolution(const EvolveConfig& config, const std::string& out_path,
                        const RunOptions& opt) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto say = [&](const std::string& m) {
    if (opt.on_message) opt.on_message(m);
  };
  RunReport report;
  const int requested = opt.threads >= 0 ? opt.threads : config.threads;
  report.threads = requested > 0 ? requested : hardware_threads();

  Cluster* cluster = opt.cluster;
  const bool leader = !cluster || cluster->rank() == 0;

  // Rank 0 (or the single process) decides; the others follow.
  std::string decision = "new";
  std::optional<ResultsFile> found;
  std::optional<RunLock> lock;
  if (leader) {
    try {
      lock.emplace(out_path);
      if (std::filesystem::exists(out_path)) {
        found = read_results(out_path);  // a one-line error if unreadable
        const std::string diff = config_difference(found->state.config, config);
        if (!diff.empty())
          throw ResultsError(out_path + ": written by a different configuration (" + diff +
                             "); refusing to resume. Use the original config or another "
                             "--out file");
        const auto scorer = [](const std::string& f) { return f.empty() ? "built-in" : f; };
        if (scorer(found->provenance.fitness_function) != scorer(opt.fitness_function))
          throw ResultsError(out_path + ": scored by fitness " +
                             scorer(found->provenance.fitness_function) + ", now by " +
                             scorer(opt.fitness_function) +
                             "; refusing to resume. Use the same fitness or another --out file");
        decision = "resume";
      }
      if (!lock->unwritable().empty() && !(found && found->state.finished()))
        throw ResultsError(lock->unwritable() +
                           " (the run is not finished, so it must be "
                           "written)");
    } catch (const std::exception& e) {
      if (!cluster) throw;
      decision = std::string("error:") + e.what();
    }
  }
  if (cluster) cluster->broadcast(decision);
  if (decision.rfind("error:", 0) == 0) throw RunRefused(decision.substr(6));

  RunState state = Evolver::new_run(config);
  Provenance prov = current_provenance(report.threads);
  if (cluster) prov.threads = static_cast<int64_t>(report.threads) * cluster->size();
  prov.fitness_function = opt.fitness_function.empty() ? "built-in" : opt.fitness_function;
  if (decision == "resume") {
    ResultsFile f = found ? std::move(*found) : read_results(out_path);
    report.resumed_from = f.state.generations_done;
    report.generations_done = f.state.generations_done;
    report.content_digest = f.content_digest;
    if (f.state.finished()) {
      report.outcome = RunOutcome::kAlreadyFinished;
      return report;
    }
    if (leader)
      say(out_path + ": resuming after generation " + std::to_string(f.state.generations_done));
    // Run-control fields (threads, checkpoint_every) come from the current config.
    f.state.config = config;
    state = std::move(f.state);
    prov.date_created = f.provenance.date_created;
    prov.wall_seconds = f.provenance.wall_seconds;
  }
  const double wall_before = prov.wall_seconds;

  Simulations* backend = cluster ? cluster : opt.simulations;
  Evolver ev(std::move(state), cluster || !opt.simulations ? report.threads : 1, backend);
  const int first_gen_this_session = ev.state().generations_done + 1;
  while (!ev.finished()) {
    RunProgress p;
    p.stats = ev.step();
    p.generations_done = ev.state().generations_done;
    p.generations_total = config.generations;
    bool stop = opt.stop_after >= 0 && p.generations_done >= opt.stop_after;
    if (opt.stop_requested) {
      std::string asked = opt.stop_requested->load() ? "1" : "0";
      if (cluster) cluster->broadcast(asked);  // rank 0 decides for all
      stop = stop || asked == "1";
    }
    if (leader && (p.generations_done % config.checkpoint_every == 0 || ev.finished() || stop)) {
      const auto tc = Clock::now();
      prov.date_updated = current_provenance(report.threads).date_updated;
      prov.wall_seconds = wall_before + std::chrono::duration<double>(Clock::now() - t0).count();
      write_results(out_path, ev.state(), prov);
      p.checkpointed = true;
      p.checkpoint_seconds = std::chrono::duration<double>(Clock::now() - tc).count();
    }
    p.session_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const int done_here = p.generations_done - first_gen_this_session + 1;
    p.eta_seconds = p.session_seconds / done_here * (config.generations - p.generations_done);
    if (leader && opt.on_generation) opt.on_generation(p);
    if (stop && !ev.finished()) {
      report.outcome = RunOutcome::kStopped;
      report.generations_done = ev.state().generations_done;
      report.content_digest = content_digest(ev.state()).hex();
      return report;
    }
  }
  report.outcome = RunOutcome::kFinished;
  report.generations_done = ev.state().generations_done;
  report.content_digest = content_digest(ev.state()).hex();
  return report;
}

}  // namespace plastivox::evo
