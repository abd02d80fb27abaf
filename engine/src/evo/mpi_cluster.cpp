#include "plastivox/evo/mpi_cluster.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <stdexcept>

namespace plastivox::evo {
namespace {

// Evaluation <-> bytes: index u64, fitness f64, status u8, sank u8, failure (u64 length + bytes),
// final stiffness (u64 count + f64s). Same machine architecture on every rank.
template <class T>
void put(std::vector<char>& b, const T& v) {
  const char* p = reinterpret_cast<const char*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}

template <class T>
T get(const std::vector<char>& b, size_t& at) {
  if (at + sizeof(T) > b.size()) throw std::runtime_error("MPI: truncated evaluation message");
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

void pack(std::vector<char>& b, uint64_t index, const Evaluation& e) {
  put(b, index);
  put(b, e.fitness);
  put(b, static_cast<uint8_t>(e.status));
  put(b, static_cast<uint8_t>(e.sank ? 1 : 0));
  put(b, static_cast<uint64_t>(e.failure.size()));
  b.insert(b.end(), e.failure.begin(), e.failure.end());
  put(b, static_cast<uint64_t>(e.final_stiffness.size()));
  for (double x : e.final_stiffness) put(b, x);
  put(b, e.wall_seconds);
}

}  // namespace

bool MpiCluster::launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

MpiCluster::MpiCluster() {
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Init_thread failed");
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiCluster::~MpiCluster() {
  MPI_Finalize();
}

void MpiCluster::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

void MpiCluster::broadcast(std::string& text) {
  uint64_t n = text.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  text.resize(n);
  if (n > 0) MPI_Bcast(text.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
}

void MpiCluster::barrier() {
  MPI_Barrier(MPI_COMM_WORLD);
}

std::vector<int> assign_to_ranks(const std::vector<const Phenotype*>& batch, int ranks) {
  std::vector<size_t> order(batch.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return batch[a]->voxels > batch[b]->voxels; });
  std::vector<int64_t> load(ranks, 0);
  std::vector<int> owner(batch.size(), 0);
  for (size_t i : order) {
    const int r = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[i] = r;
    load[r] += 1 + batch[i]->voxels;
  }
  return owner;
}

std::vector<Evaluation> MpiCluster::run(const std::vector<const Phenotype*>& batch,
                                        const PhysicsDef& physics, int threads) {
  // Every rank computes the same assignment and simulates its share.
  const std::vector<int> owner = assign_to_ranks(batch, size_);
  std::vector<size_t> mine;
  std::vector<const Phenotype*> share;
  for (size_t i = 0; i < batch.size(); ++i)
    if (owner[i] == rank_) {
      mine.push_back(i);
      share.push_back(batch[i]);
    }
  const std::vector<Evaluation> done = simulate_on_threads(share, physics, threads);
  std::vector<char> out;
  for (size_t k = 0; k < mine.size(); ++k) pack(out, mine[k], done[k]);

  // Exchange: sizes, then bytes.
  int my_bytes = static_cast<int>(out.size());
  std::vector<int> sizes(size_), displs(size_, 0);
  MPI_Allgather(&my_bytes, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + sizes[r - 1];
  std::vector<char> all(static_cast<size_t>(displs.back()) + sizes.back());
  MPI_Allgatherv(out.data(), my_bytes, MPI_BYTE, all.data(), sizes.data(), displs.data(), MPI_BYTE,
                 MPI_COMM_WORLD);

  std::vector<Evaluation> results(batch.size());
  std::vector<uint8_t> filled(batch.size(), 0);
  size_t at = 0;
  while (at < all.size()) {
    const auto index = get<uint64_t>(all, at);
    if (index >= batch.size()) throw std::runtime_error("MPI: evaluation index out of range");
    Evaluation& e = results[index];
    e.fitness = get<double>(all, at);
    e.status = static_cast<EvalStatus>(get<uint8_t>(all, at));
    e.sank = get<uint8_t>(all, at) != 0;
    const auto len = get<uint64_t>(all, at);
    if (at + len > all.size()) throw std::runtime_error("MPI: truncated evaluation message");
    e.failure.assign(all.data() + at, len);
    at += len;
    const auto count = get<uint64_t>(all, at);
    e.final_stiffness.resize(count);
    for (double& x : e.final_stiffness) x = get<double>(all, at);
    e.wall_seconds = get<double>(all, at);
    filled[index] = 1;
  }
  for (uint8_t f : filled)
    if (!f) throw std::runtime_error("MPI: a simulation result is missing");
  return results;
}

}  // namespace plastivox::evo
