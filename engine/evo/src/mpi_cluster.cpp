#include "plastivox/evo/mpi_cluster.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <type_traits>

#include "plastivox/evo/eval_pool.hpp"
#include "plastivox/io/robot_file.hpp"

namespace plastivox::evo {
namespace {

// Evaluation <-> bytes: index u64, fitness f64, status u8, sank u8, failure (u64 length + bytes),
// final stiffness (u64 count + f64s), the life's measures (u8 + 3 f64), wall seconds. Same
// machine architecture on every rank.
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
  put(b, static_cast<uint8_t>(e.vertical ? 1 : 0));
  put(b, static_cast<uint64_t>(e.failure.size()));
  b.insert(b.end(), e.failure.begin(), e.failure.end());
  put(b, static_cast<uint64_t>(e.final_stiffness.size()));
  for (double x : e.final_stiffness) put(b, x);
  put(b, static_cast<uint8_t>(e.measures.measured ? 1 : 0));
  put(b, e.measures.floor_contact);
  put(b, e.measures.com_height);
  put(b, e.measures.development);
  put(b, e.wall_seconds);
}

// The rest of pack(): an evaluation after its index.
Evaluation unpack(const std::vector<char>& b, size_t& at) {
  Evaluation e;
  e.fitness = get<double>(b, at);
  e.status = static_cast<EvalStatus>(get<uint8_t>(b, at));
  e.sank = get<uint8_t>(b, at) != 0;
  e.vertical = get<uint8_t>(b, at) != 0;
  const auto len = get<uint64_t>(b, at);
  if (at + len > b.size()) throw std::runtime_error("MPI: truncated evaluation message");
  e.failure.assign(b.data() + at, len);
  at += len;
  const auto count = get<uint64_t>(b, at);
  if (count > (b.size() - at) / sizeof(double))
    throw std::runtime_error("MPI: truncated evaluation message");
  e.final_stiffness.resize(count);
  for (double& x : e.final_stiffness) x = get<double>(b, at);
  e.measures.measured = get<uint8_t>(b, at) != 0;
  e.measures.floor_contact = get<double>(b, at);
  e.measures.com_height = get<double>(b, at);
  e.measures.development = get<double>(b, at);
  e.wall_seconds = get<double>(b, at);
  return e;
}

template <class T>
void put_array(std::vector<char>& b, const std::vector<T>& v) {
  put(b, static_cast<uint64_t>(v.size()));
  const char* p = reinterpret_cast<const char*>(v.data());
  b.insert(b.end(), p, p + v.size() * sizeof(T));
}

template <class T>
std::vector<T> get_array(const std::vector<char>& b, size_t& at) {
  const auto n = get<uint64_t>(b, at);
  if (n > (b.size() - at) / sizeof(T)) throw std::runtime_error("MPI: truncated body message");
  std::vector<T> v(n);
  if (n > 0) std::memcpy(v.data(), b.data() + at, n * sizeof(T));  // no null pointer when empty
  at += n * sizeof(T);
  return v;
}

// A simulation for another rank: id u64, physics (physics_to_json, u64 length + bytes: exact
// for every field; the environment holds arrays, so PhysicsDef is not sent as bytes), lattice
// extent and voxel size, voxel count, the four lattice arrays, then the controller (kind,
// hidden, every, weights).
void pack_body(std::vector<char>& b, uint64_t id, const Phenotype& p, const PhysicsDef& physics) {
  const RobotDef& r = p.robot;
  if (!r.fixed_sites.empty() || !r.loads.empty())
    throw std::logic_error("MPI: an evolved body has no boundary conditions");
  put(b, id);
  const std::string physics_text = physics_to_json(physics);
  put(b, static_cast<uint64_t>(physics_text.size()));
  b.insert(b.end(), physics_text.begin(), physics_text.end());
  put(b, r.nx);
  put(b, r.ny);
  put(b, r.nz);
  put(b, r.voxel_size);
  put(b, p.voxels);
  put_array(b, r.present);
  put_array(b, r.stiffness);
  put_array(b, r.dev_rate);
  put_array(b, r.phase);
  put(b, static_cast<int>(r.controller.kind));
  put(b, r.controller.hidden);
  put(b, r.controller.every);
  put_array(b, r.controller.weights);
}

struct RemoteBody {
  uint64_t id = 0;
  PhysicsDef physics;
  Phenotype body;
};

RemoteBody unpack_body(const std::vector<char>& b) {
  RemoteBody t;
  size_t at = 0;
  t.id = get<uint64_t>(b, at);
  const auto len = get<uint64_t>(b, at);
  if (at + len > b.size()) throw std::runtime_error("MPI: truncated body message");
  apply_physics_json(std::string(b.data() + at, len), "MPI body message", t.physics);
  at += len;
  RobotDef& r = t.body.robot;
  r.nx = get<int>(b, at);
  r.ny = get<int>(b, at);
  r.nz = get<int>(b, at);
  r.voxel_size = get<double>(b, at);
  t.body.voxels = get<int>(b, at);
  r.present = get_array<uint8_t>(b, at);
  r.stiffness = get_array<double>(b, at);
  r.dev_rate = get_array<double>(b, at);
  r.phase = get_array<double>(b, at);
  r.controller.kind = static_cast<ControllerKind>(get<int>(b, at));
  r.controller.hidden = get<int>(b, at);
  r.controller.every = get<int>(b, at);
  r.controller.weights = get_array<double>(b, at);
  t.body.valid = true;
  return t;
}

constexpr int kTagBody = 71, kTagResult = 72, kTagRelease = 73;

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

std::vector<std::string> MpiCluster::allgather(const std::string& mine) {
  int my_bytes = static_cast<int>(mine.size());
  std::vector<int> sizes(size_), displs(size_, 0);
  MPI_Allgather(&my_bytes, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + sizes[r - 1];
  std::vector<char> all(static_cast<size_t>(displs.back()) + sizes.back());
  MPI_Allgatherv(mine.data(), my_bytes, MPI_BYTE, all.data(), sizes.data(), displs.data(), MPI_BYTE,
                 MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int r = 0; r < size_; ++r) out.emplace_back(all.data() + displs[r], sizes[r]);
  return out;
}

std::vector<int> assign_by_cost(const std::vector<double>& cost, int ranks) {
  std::vector<size_t> order(cost.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  std::vector<double> load(static_cast<size_t>(ranks), 0.0);
  std::vector<int> owner(cost.size(), 0);
  for (size_t i : order) {
    const auto r = static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[i] = static_cast<int>(r);
    load[r] += cost[i];
  }
  return owner;
}

std::vector<int> assign_to_ranks(const std::vector<const Phenotype*>& batch, int ranks) {
  std::vector<double> cost(batch.size());  // whole numbers: sums exact in a double
  for (size_t i = 0; i < batch.size(); ++i) cost[i] = 1.0 + batch[i]->voxels;
  return assign_by_cost(cost, ranks);
}

void MpiCluster::serve(EvaluationPool& pool, const std::function<bool()>& finished) {
  int none = 0;
  std::vector<int> capacity(size_, 0);  // threads of each rank
  MPI_Gather(&none, 1, MPI_INT, capacity.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> out(size_, 0);
  std::map<uint64_t, EvaluationPool::Claim> sent;
  uint64_t next_id = 0;
  std::vector<char> buf;
  for (;;) {
    bool busy = false;
    for (int r = 1; r < size_; ++r) {
      EvaluationPool::Claim c;
      while (out[r] < capacity[r] && pool.try_claim(c)) {
        buf.clear();
        pack_body(buf, next_id, *c.body, *c.physics);
        MPI_Send(buf.data(), static_cast<int>(buf.size()), MPI_BYTE, r, kTagBody, MPI_COMM_WORLD);
        sent[next_id++] = c;
        ++out[r];
        busy = true;
      }
    }
    for (;;) {
      int arrived = 0;
      MPI_Status st;
      MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, MPI_COMM_WORLD, &arrived, &st);
      if (!arrived) break;
      int bytes = 0;
      MPI_Get_count(&st, MPI_BYTE, &bytes);
      buf.resize(static_cast<size_t>(bytes));
      MPI_Recv(buf.data(), bytes, MPI_BYTE, st.MPI_SOURCE, kTagResult, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      size_t at = 0;
      const auto id = get<uint64_t>(buf, at);
      const auto it = sent.find(id);
      if (it == sent.end()) throw std::runtime_error("MPI: a result for no body sent");
      pool.complete(it->second, unpack(buf, at));
      sent.erase(it);
      --out[st.MPI_SOURCE];
      busy = true;
    }
    if (sent.empty() && finished()) break;
    if (!busy) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  for (int r = 1; r < size_; ++r) MPI_Send(nullptr, 0, MPI_BYTE, r, kTagRelease, MPI_COMM_WORLD);
}

void MpiCluster::work(int threads) {
  int mine = threads;
  MPI_Gather(&mine, 1, MPI_INT, nullptr, 0, MPI_INT, 0, MPI_COMM_WORLD);
  // Bodies in, packed results out; the threads simulate, the main thread talks MPI.
  std::mutex m;
  std::condition_variable arrived;
  std::deque<RemoteBody> inbox;
  std::deque<std::vector<char>> outbox;
  bool released = false;
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      std::unique_lock<std::mutex> lock(m);
      for (;;) {
        arrived.wait(lock, [&] { return released || !inbox.empty(); });
        if (inbox.empty()) return;
        RemoteBody job = std::move(inbox.front());
        inbox.pop_front();
        lock.unlock();
        std::vector<char> result;
        try {
          pack(result, job.id, evaluate_phenotype(job.body, job.physics));
        } catch (const std::exception& e) {  // rank 0 would wait for ever
          std::fprintf(stderr, "plastivox: rank %d: error: %s\n", rank_, e.what());
          abort(1);
        }
        lock.lock();
        outbox.push_back(std::move(result));
      }
    });
  std::vector<char> buf;
  for (bool done = false; !done;) {
    bool busy = false;
    {
      std::deque<std::vector<char>> ready;
      {
        std::lock_guard<std::mutex> lock(m);
        ready.swap(outbox);
      }
      for (const auto& r : ready)
        MPI_Send(r.data(), static_cast<int>(r.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD);
      busy = !ready.empty();
    }
    int got = 0;
    MPI_Status st;
    MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &got, &st);
    if (got) {
      int bytes = 0;
      MPI_Get_count(&st, MPI_BYTE, &bytes);
      buf.resize(static_cast<size_t>(bytes));
      MPI_Recv(buf.data(), bytes, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (st.MPI_TAG == kTagRelease) {
        done = true;  // rank 0 releases only when nothing is out
      } else {
        RemoteBody job = unpack_body(buf);
        std::lock_guard<std::mutex> lock(m);
        inbox.push_back(std::move(job));
        arrived.notify_one();
      }
      busy = true;
    }
    if (!busy) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  {
    std::lock_guard<std::mutex> lock(m);
    released = true;
  }
  arrived.notify_all();
  for (std::thread& t : pool) t.join();
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

  // Exchange: every rank's results, in rank order.
  std::vector<char> all;
  for (const std::string& part : allgather(std::string(out.begin(), out.end())))
    all.insert(all.end(), part.begin(), part.end());

  std::vector<Evaluation> results(batch.size());
  std::vector<uint8_t> filled(batch.size(), 0);
  size_t at = 0;
  while (at < all.size()) {
    const auto index = get<uint64_t>(all, at);
    if (index >= batch.size()) throw std::runtime_error("MPI: evaluation index out of range");
    results[index] = unpack(all, at);
    filled[index] = 1;
  }
  for (uint8_t f : filled)
    if (!f) throw std::runtime_error("MPI: a simulation result is missing");
  return results;
}

}  // namespace plastivox::evo
