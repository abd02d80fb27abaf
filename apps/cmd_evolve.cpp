// plastivox evolve: run (or resume) an evolution described by a config file into an HDF5
// results file; or print the default config.
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "cli.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/robot_file.hpp"
#ifdef PLASTIVOX_HAVE_MPI
#include "plastivox/evo/mpi_cluster.hpp"
#endif

namespace plastivox::cli {
namespace {

int parse_count(const std::string& s, const std::string& option) {
  size_t used = 0;
  long v = -1;
  try {
    v = std::stol(s, &used);
  } catch (...) {
    used = 0;
  }
  if (used != s.size() || v < 0 || v > 1 << 20)
    throw UsageError{option + " expects a non-negative integer, got '" + s + "'"};
  return static_cast<int>(v);
}

std::string duration(double s) {
  char buf[64];
  if (!(s >= 0) || s > 1e9) return "?";
  const long t = static_cast<long>(s + 0.5);
  if (t >= 3600)
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, (t % 3600) / 60);
  else if (t >= 60)
    std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
  else
    std::snprintf(buf, sizeof buf, "%lds", t);
  return buf;
}

// Progress on stderr: one updating status line on a terminal, plain log lines otherwise.
class Progress {
 public:
  Progress() : tty_(isatty(STDERR_FILENO) == 1) {}
  ~Progress() { end_line(); }

  void message(const std::string& m) {
    end_line();
    std::fprintf(stderr, "plastivox evolve: %s\n", m.c_str());
  }

  void generation(const evo::RunProgress& p) {
    const evo::GenerationStats& s = p.stats;
    const double rate = s.wall_seconds > 0 ? s.simulated / s.wall_seconds : 0.0;
    if (tty_) {
      std::fprintf(stderr, "\r\033[Kgeneration %d/%d  best %.4f (id %llu)  %.2f evals/s  left %s",
                   p.generations_done, p.generations_total, s.best_fitness,
                   static_cast<unsigned long long>(s.champion_id), rate,
                   duration(p.eta_seconds).c_str());
      std::fflush(stderr);
      open_ = true;
    } else {
      char ckpt[64] = "";
      if (p.checkpointed)
        std::snprintf(ckpt, sizeof ckpt, "; checkpoint %.3f s", p.checkpoint_seconds);
      std::fprintf(
          stderr,
          "generation %d/%d: best %.6f (id %llu); %d new: %d simulated, %d cached, %d "
          "invalid, %d unstable, %d sank through the floor; %.2f evals/s; %.2f s (simulation "
          "%.2f s)%s; left %s\n",
          p.generations_done, p.generations_total, s.best_fitness,
          static_cast<unsigned long long>(s.champion_id), s.created, s.simulated, s.cache_hits,
          s.invalid, s.unstable, s.sank, rate, s.wall_seconds, s.sim_wall_seconds, ckpt,
          duration(p.eta_seconds).c_str());
    }
  }

  void end_line() {
    if (open_) std::fputc('\n', stderr);
    open_ = false;
  }

 private:
  bool tty_;
  bool open_ = false;
};

}  // namespace

int cmd_evolve(const Args& in) {
  Args args = in;
  const bool print_default = take_flag(args, "--print-default-config");
  const std::string config_path = take_option(args, "--config", "");
  const std::string out = take_option(args, "--out", "");
  const std::string threads = take_option(args, "--threads", "");
  // Testing hook (undocumented in the usage): stop after this many generations, as if
  // killed right after a checkpoint.
  const std::string stop_after = take_option(args, "--stop-after", "");
  reject_unknown_options(args);
  if (!args.empty()) throw UsageError{"unexpected argument '" + args[0] + "'"};
  if (print_default) {
    if (!config_path.empty() || !out.empty())
      throw UsageError{"--print-default-config takes no other options"};
    std::fputs(evo::default_config_text().c_str(), stdout);
    return 0;
  }
  if (config_path.empty()) throw UsageError{"--config FILE is required"};
  if (out.empty()) throw UsageError{"--out RESULTS.h5 is required"};

  evo::RunOptions opt;
  if (!threads.empty()) opt.threads = parse_count(threads, "--threads");
  if (!stop_after.empty()) opt.stop_after = parse_count(stop_after, "--stop-after");

    // Under mpirun every rank runs this; rank 0 alone talks (run.hpp, mpi_cluster.hpp).
#ifdef PLASTIVOX_HAVE_MPI
  std::unique_ptr<evo::MpiCluster> mpi;
  if (evo::MpiCluster::launched_by_mpirun()) mpi = std::make_unique<evo::MpiCluster>();
  opt.cluster = mpi.get();
#endif
  const bool leader = !opt.cluster || opt.cluster->rank() == 0;
  // Ctrl-C or SIGTERM: finish the generation, checkpoint, exit 130 (rank 0 decides under MPI).
  opt.stop_requested = install_stop_signals("evolve");
  Progress progress;
  evo::RunReport r;
  try {
    const evo::EvolveConfig config = evo::read_config_file(config_path);
    opt.on_message = [&](const std::string& m) { progress.message(m); };
    opt.on_generation = [&](const evo::RunProgress& p) { progress.generation(p); };
    r = evo::run_evolution(config, out, opt);
  } catch (const InputError& e) {  // the same config file on every rank: all fail alike
    if (!opt.cluster) throw;
    return refuse_together(*opt.cluster, "evolve", e.what());
  } catch (const evo::RunRefused& e) {  // decided by rank 0, raised on every rank
    if (!opt.cluster) throw;
    return refuse_together(*opt.cluster, "evolve", e.what());
  } catch (const std::exception& e) {
#ifdef PLASTIVOX_HAVE_MPI
    if (mpi && mpi->size() > 1) {  // the other ranks would wait forever
      std::fprintf(stderr, "plastivox evolve: rank %d: error: %s\n", mpi->rank(), e.what());
      mpi->abort(1);
    }
#endif
    throw;
  }
  progress.end_line();
  if (!leader) return 0;
  switch (r.outcome) {
    case evo::RunOutcome::kAlreadyFinished:
      std::printf("%s: already finished (%s); nothing changed\n", out.c_str(),
                  count_of(r.generations_done, "generation").c_str());
      break;
    case evo::RunOutcome::kStopped:
      std::printf("%s: stopped after generation %d (resumable)\n", out.c_str(), r.generations_done);
      if (opt.stop_requested->load()) {
        std::fprintf(stderr, "plastivox evolve: stopped; run the same command again to resume\n");
        return 130;
      }
      break;
    case evo::RunOutcome::kFinished:
      std::printf("%s: finished %s on %s; content digest %s\n", out.c_str(),
                  count_of(r.generations_done, "generation").c_str(),
                  count_of(r.threads, "thread").c_str(), r.content_digest.c_str());
      break;
  }
  return 0;
}

}  // namespace plastivox::cli
