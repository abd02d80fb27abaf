#include "cli.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "plastivox/evo/run.hpp"
#ifdef PLASTIVOX_HAVE_MPI
#include "plastivox/evo/mpi_cluster.hpp"
#endif

namespace plastivox::cli {
namespace {

std::atomic<bool> g_stop{false};
char g_stop_message[160] = "";

// First signal: ask for a stop at the next checkpoint. Second: leave at once (every file is
// written atomically, so even that loses at most the work in flight).
extern "C" void on_stop_signal(int) {
  if (g_stop.exchange(true)) _exit(130);
  [[maybe_unused]] auto n = write(STDERR_FILENO, g_stop_message, std::strlen(g_stop_message));
}

}  // namespace

const std::atomic<bool>* install_stop_signals(const char* command) {
  std::snprintf(g_stop_message, sizeof g_stop_message,
                "\nplastivox %s: stopping at the next checkpoint (Ctrl-C again to quit now)\n",
                command);
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  return &g_stop;
}

namespace {

// Removes the first "--name VALUE" from args into value; false when --name is absent.
bool take_one(Args& args, const std::string& name, std::string& value) {
  auto it = std::find(args.begin(), args.end(), name);
  if (it == args.end()) return false;
  if (it + 1 == args.end()) throw UsageError{"option " + name + " needs a value"};
  value = *(it + 1);
  // Empty is never a value: it would read as "not given" (or as 0) without a word.
  if (value.empty()) throw UsageError{"option " + name + " needs a value, got ''"};
  // Nor is another option: "--out --time 2" would write a file named "--time".
  if (value.starts_with("--"))
    throw UsageError{"option " + name + " needs a value, got the option " + value};
  args.erase(it, it + 2);
  return true;
}

}  // namespace

std::string take_option(Args& args, const std::string& name, const std::string& fallback) {
  std::string value;
  if (!take_one(args, name, value)) return fallback;
  if (std::find(args.begin(), args.end(), name) != args.end())
    throw UsageError{"option " + name + " is given more than once"};
  return value;
}

std::vector<std::string> take_repeated_option(Args& args, const std::string& name) {
  std::vector<std::string> values;
  for (std::string v; take_one(args, name, v);) values.push_back(v);
  return values;
}

int parse_count(const std::string& s, const std::string& option) {
  size_t used = 0;
  long v = -1;
  try {
    v = std::stol(s, &used);
  } catch (...) {
    used = 0;
  }
  if (s.empty() || used != s.size() || v < 0 || v > 1 << 20)
    throw UsageError{option + " expects a non-negative integer, got '" + s + "'"};
  return static_cast<int>(v);
}

bool read_number(const std::string& text, double& v) {
  size_t used = 0;
  v = 0;
  // Decimal only: std::stod also reads hexadecimal ("0x0"), "inf" and "nan".
  if (text.find_first_not_of("0123456789+-.eE") != std::string::npos) return false;
  try {
    v = std::stod(text, &used);
  } catch (...) {
    used = 0;
  }
  return !text.empty() && used == text.size();
}

bool take_flag(Args& args, const std::string& name) {
  auto it = std::find(args.begin(), args.end(), name);
  if (it == args.end()) return false;
  args.erase(it);
  return true;
}

std::string count_of(long long n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

void reject_unknown_options(const Args& args) {
  for (const std::string& a : args)
    if (a.size() > 1 && a[0] == '-') throw UsageError{"unknown option " + a};
}

std::unique_ptr<evo::Cluster> join_mpi_job() {
#ifdef PLASTIVOX_HAVE_MPI
  if (evo::MpiCluster::launched_by_mpirun()) return std::make_unique<evo::MpiCluster>();
#endif
  return nullptr;
}

void abort_other_ranks(evo::Cluster* cluster, const char* cmd, const std::exception& e) {
#ifdef PLASTIVOX_HAVE_MPI
  auto* mpi = dynamic_cast<evo::MpiCluster*>(cluster);
  if (mpi && mpi->size() > 1) {
    std::fprintf(stderr, "plastivox %s: rank %d: error: %s\n", cmd, mpi->rank(), e.what());
    mpi->abort(1);
  }
#else
  (void)cluster, (void)cmd, (void)e;
#endif
}

int refuse_together(evo::Cluster& cluster, const std::string& cmd, const std::string& message) {
  if (cluster.rank() == 0) {
    std::fprintf(stderr, "plastivox %s: error: %s\n", cmd.c_str(), message.c_str());
    std::fflush(stderr);
  }
  cluster.barrier();
  return cluster.rank() == 0 ? 1 : 0;
}

}  // namespace plastivox::cli
