#include "battery_ranks.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "plastivox/base/parallel.hpp"
#include "plastivox/io/limits.hpp"
#ifdef PLASTIVOX_HAVE_MPI
#include "plastivox/evo/mpi_cluster.hpp"
#endif

namespace plastivox::cli {
namespace {

// Outcome <-> bytes: index u64, fitness f64 (its bits), status and failure (u64 length + bytes).
template <class T>
void put(std::string& b, const T& v) {
  b.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T get(const std::string& b, size_t& at) {
  if (at + sizeof(T) > b.size()) throw std::runtime_error("MPI: truncated battery message");
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

void put_text(std::string& b, const std::string& s) {
  put(b, static_cast<uint64_t>(s.size()));
  b += s;
}

std::string get_text(const std::string& b, size_t& at) {
  const auto n = get<uint64_t>(b, at);
  if (n > b.size() - at) throw std::runtime_error("MPI: truncated battery message");
  std::string s = b.substr(at, n);
  at += n;
  return s;
}

}  // namespace

BatteryLives battery_lives_over_ranks(evo::Cluster* cluster, int threads) {
#ifdef PLASTIVOX_HAVE_MPI
  auto* mpi = dynamic_cast<evo::MpiCluster*>(cluster);
  if (!mpi || mpi->size() < 2) return {};
  return [mpi, threads](const std::vector<analysis::PerturbedLife>& lives) {
    const Limits limits = limits_from_environment();
    std::vector<double> cost(lives.size());
    for (size_t i = 0; i < lives.size(); ++i) cost[i] = analysis::life_voxel_steps(lives[i]);
    const std::vector<int> owner = evo::assign_by_cost(cost, mpi->size());
    std::vector<size_t> mine;
    for (size_t i = 0; i < lives.size(); ++i)
      if (owner[i] == mpi->rank()) mine.push_back(i);
    std::stable_sort(mine.begin(), mine.end(),  // longest first on this rank's threads
                     [&](size_t a, size_t b) { return cost[a] > cost[b]; });
    std::vector<analysis::BatteryRun> done(mine.size());
    parallel_for(mine.size(), threads > 0 ? threads : hardware_threads(),
                 [&](size_t k) { done[k] = analysis::run_battery_life(lives[mine[k]], limits); });
    std::string bytes;
    for (size_t k = 0; k < mine.size(); ++k) {
      put(bytes, static_cast<uint64_t>(mine[k]));
      put(bytes, done[k].fitness);
      put_text(bytes, done[k].status);
      put_text(bytes, done[k].failure);
    }
    std::vector<analysis::BatteryRun> out(lives.size());
    std::vector<uint8_t> filled(lives.size(), 0);
    for (const std::string& b : mpi->allgather(bytes))
      for (size_t at = 0; at < b.size();) {
        const auto i = get<uint64_t>(b, at);
        if (i >= lives.size()) throw std::runtime_error("MPI: battery life index out of range");
        out[i].fitness = get<double>(b, at);
        out[i].status = get_text(b, at);
        out[i].failure = get_text(b, at);
        filled[i] = 1;
      }
    if (std::count(filled.begin(), filled.end(), 0) > 0)
      throw std::runtime_error("MPI: a battery life's outcome is missing");
    return out;
  };
#else
  (void)cluster, (void)threads;
  return {};
#endif
}

}  // namespace plastivox::cli
