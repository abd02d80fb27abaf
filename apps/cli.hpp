// The plastivox command line: one function per subcommand, shared argument helpers.
#pragma once

#include <atomic>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/base/error.hpp"

namespace plastivox::evo {
class Cluster;
}

namespace plastivox::cli {

using Args = std::vector<std::string>;

// A malformed command line throws UsageError (plastivox/base/error.hpp); main prints the
// message and exits with status 2.

int cmd_simulate(const Args& args);
int cmd_demo(const Args& args);
int cmd_evolve(const Args& args);      // apps/cmd_evolve.cpp
int cmd_inspect(const Args& args);     // apps/cmd_inspect.cpp
int cmd_hausdorff(const Args& args);   // apps/cmd_hausdorff.cpp
int cmd_export(const Args& args);      // apps/cmd_export.cpp
int cmd_analyze(const Args& args);     // apps/cmd_analyze.cpp
int cmd_robustness(const Args& args);  // apps/cmd_robustness.cpp
int cmd_render(const Args& args);      // apps/cmd_render.cpp
int cmd_video(const Args& args);       // apps/cmd_video.cpp
int cmd_view(const Args& args);        // apps/cmd_view.cpp
int cmd_gallery(const Args& args);     // apps/cmd_gallery.cpp
int cmd_figures(const Args& args);     // apps/cmd_figures.cpp
int cmd_archive(const Args& args);     // apps/cmd_archive.cpp
int cmd_experiment(const Args& args);  // apps/cmd_experiment.cpp
int cmd_optimize(const Args& args);    // apps/cmd_optimize.cpp

// The usage text of one command (apps/help.cpp), or nullptr for an unknown command.
const char* command_help(const std::string& command);
// Whether args ask for help (--help or -h).
bool wants_help(const Args& args);
// "1 thread", "2 threads": a count and its noun, plural by appending "s".
std::string count_of(long long n, const std::string& noun);

// Removes "--name VALUE" from args and returns VALUE (or fallback when absent). The value
// may be neither empty nor another option, and the option may be given once (UsageError).
std::string take_option(Args& args, const std::string& name, const std::string& fallback);
// Every VALUE of an option that may be repeated ("--config A --config B"), in order.
std::vector<std::string> take_repeated_option(Args& args, const std::string& name);
// A non-negative whole number (at most 2^20) given to `option`; UsageError otherwise.
int parse_count(const std::string& s, const std::string& option);
// Reads `text` as one decimal number into v: false when it is empty, not a number (or
// hexadecimal, inf or nan) or has more after it.
bool read_number(const std::string& text, double& v);
// Removes "--name" from args and returns whether it was there.
bool take_flag(Args& args, const std::string& name);
// After options are taken: error on any leftover "--something".
void reject_unknown_options(const Args& args);

// Graceful stop for long commands (evolve, experiment): the first SIGINT or SIGTERM prints
// "plastivox COMMAND: stopping at the next checkpoint ..." and sets the returned flag (the
// command checkpoints, stops and exits 130); a second one exits 130 at once. SIGTERM is
// always caught, so a background process (which inherits SIGINT ignored) stops on it too.
// Call once per process; `command` must outlive it (a string literal).
const std::atomic<bool>* install_stop_signals(const char* command);

// An error every MPI rank raised alike: rank 0 prints "plastivox CMD: error: MESSAGE" and
// returns 1; the others wait until it has printed and return 0, so mpirun cannot kill rank 0
// before its line is out (mpirun still exits non-zero because rank 0 did).
int refuse_together(evo::Cluster& cluster, const std::string& cmd, const std::string& message);

// Under mpirun, this process's place in the MPI job (MPI initialised; keep it alive while
// the work runs); otherwise, and in builds without MPI, null: a single process.
std::unique_ptr<evo::Cluster> join_mpi_job();
// For an error only this rank has seen: under an MPI job of several ranks, prints it with the
// rank and ends every rank (MPI_Abort); otherwise returns, for the caller to rethrow.
void abort_other_ranks(evo::Cluster* cluster, const char* cmd, const std::exception& e);

}  // namespace plastivox::cli
