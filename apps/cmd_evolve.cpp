// plastivox evolve: run (or resume) an evolution described by a config file into an HDF5
// results file; or print the default config.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/task.hpp"

namespace plastivox::cli {
namespace {

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

  void generation(const evo::RunProgress& p, const std::string& who = "") {
    const evo::GenerationStats& s = p.stats;
    const double rate = s.wall_seconds > 0 ? s.simulated / s.wall_seconds : 0.0;
    if (tty_) {
      std::fprintf(stderr, "\r\033[K%sgeneration %d/%d  best %.4f (id %llu)  %.2f evals/s  left %s",
                   who.c_str(), p.generations_done, p.generations_total, s.best_fitness,
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
          "%sgeneration %d/%d: best %.6f (id %llu); %d new: %d simulated, %d cached, %d "
          "invalid, %d unstable, %d sank through the floor; %.2f evals/s; %.2f s (simulation "
          "%.2f s)%s; left %s\n",
          who.c_str(), p.generations_done, p.generations_total, s.best_fitness,
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

// The one-line outcome of a run on stdout; 130 for a stop by request.
int report_outcome(const evo::RunReport& r, const std::string& out, bool stop_requested) {
  switch (r.outcome) {
    case evo::RunOutcome::kAlreadyFinished:
      std::printf("%s: already finished (%s); nothing changed\n", out.c_str(),
                  count_of(r.generations_done, "generation").c_str());
      break;
    case evo::RunOutcome::kStopped:
      std::printf("%s: stopped after generation %d (resumable)\n", out.c_str(), r.generations_done);
      if (stop_requested) return 130;
      break;
    case evo::RunOutcome::kFinished:
      std::printf("%s: finished %s on %s; content digest %s\n", out.c_str(),
                  count_of(r.generations_done, "generation").c_str(),
                  count_of(r.threads, "thread").c_str(), r.content_digest.c_str());
      break;
  }
  return 0;
}

}  // namespace

int cmd_evolve(const Args& in) {
  Args args = in;
  const bool print_default = take_flag(args, "--print-default-config");
  // --config and --out may repeat, paired in order: several runs at once (run.hpp).
  const std::vector<std::string> config_paths = take_repeated_option(args, "--config");
  const std::vector<std::string> outs = take_repeated_option(args, "--out");
  const std::string threads = take_option(args, "--threads", "");
  const std::string task = take_option(args, "--task", "");
  // Testing hook (undocumented in the usage): stop after this many generations, as if
  // killed right after a checkpoint.
  const std::string stop_after = take_option(args, "--stop-after", "");
  reject_unknown_options(args);
  if (!args.empty()) throw UsageError{"unexpected argument '" + args[0] + "'"};
  if (print_default) {
    if (!config_paths.empty() || !outs.empty())
      throw UsageError{"--print-default-config takes no other options"};
    std::fputs(evo::default_config_text().c_str(), stdout);
    return 0;
  }
  if (config_paths.empty()) throw UsageError{"--config FILE is required"};
  if (outs.empty()) throw UsageError{"--out RESULTS.h5 is required"};
  if (outs.size() != config_paths.size())
    throw UsageError{"give one --out per --config (" + count_of(config_paths.size(), "config") +
                     ", " + count_of(outs.size(), "output") + ")"};
  for (size_t i = 0; i < outs.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      if (outs[i] == outs[k]) throw UsageError{"--out " + outs[i] + " is given twice"};
  if (!stop_after.empty() && outs.size() > 1)
    throw UsageError{"--stop-after takes a single --config"};

  std::optional<Task> task_given;
  try {
    if (!task.empty()) task_given = parse_task(task);
  } catch (const std::invalid_argument& e) {
    throw UsageError{std::string("--task: ") + e.what()};
  }

  evo::RunOptions opt;
  if (!threads.empty()) opt.threads = parse_count(threads, "--threads");
  if (!stop_after.empty()) opt.stop_after = parse_count(stop_after, "--stop-after");

  // Under mpirun every rank runs this; rank 0 alone talks (run.hpp, mpi_cluster.hpp).
  const std::unique_ptr<evo::Cluster> mpi = join_mpi_job();
  opt.cluster = mpi.get();
  const bool leader = !opt.cluster || opt.cluster->rank() == 0;
  // Ctrl-C or SIGTERM: finish the generation, checkpoint, exit 130 (rank 0 decides under MPI).
  opt.stop_requested = install_stop_signals("evolve");
  Progress progress;
  const bool several = outs.size() > 1;
  auto who = [&](size_t r) { return several ? outs[r] + ": " : std::string(); };
  std::vector<evo::RunReport> reports;
  try {
    std::vector<evo::RunSpec> specs;
    for (size_t r = 0; r < outs.size(); ++r) {
      specs.push_back({evo::read_config_file(config_paths[r]), outs[r]});
      if (task_given) evo::set_task(specs.back().config, *task_given);
    }
    if (!several) {
      // One run, under mpirun spread over every rank in lockstep.
      opt.on_message = [&](const std::string& m) { progress.message(m); };
      opt.on_generation = [&](const evo::RunProgress& p) { progress.generation(p); };
      reports.push_back(evo::run_evolution(specs[0].config, specs[0].out_path, opt));
    } else {
      // Every run at once over one evaluation pool (under mpirun: every rank's threads).
      evo::ManyRunOptions mo;
      mo.cluster = opt.cluster;
      mo.threads = opt.threads;
      mo.stop_requested = opt.stop_requested;
      mo.on_message = [&](size_t r, const std::string& m) { progress.message(who(r) + m); };
      mo.on_generation = [&](size_t r, const evo::RunProgress& p) {
        progress.generation(p, who(r));
      };
      reports = evo::run_evolutions(specs, mo);
    }
  } catch (const InputError& e) {  // the same config file on every rank: all fail alike
    if (!opt.cluster) throw;
    return refuse_together(*opt.cluster, "evolve", e.what());
  } catch (const evo::RunRefused& e) {  // decided by rank 0, raised on every rank
    if (!opt.cluster) throw;
    return refuse_together(*opt.cluster, "evolve", e.what());
  } catch (const std::exception& e) {
    abort_other_ranks(opt.cluster, "evolve", e);  // they would wait forever
    throw;
  }
  progress.end_line();
  if (!leader) return 0;
  int status = 0;
  for (size_t r = 0; r < reports.size(); ++r)
    status = std::max(status, report_outcome(reports[r], outs[r], opt.stop_requested->load()));
  if (status == 130)
    std::fprintf(stderr, "plastivox evolve: stopped; run the same command again to resume\n");
  return status;
}

}  // namespace plastivox::cli
