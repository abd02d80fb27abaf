// Evolution over MPI ranks (library plastivox_evo_mpi, built when OpenMPI is found).
//
// `mpirun -np N plastivox evolve --config F --out R.h5` runs N ranks of the same
// deterministic evolver in lockstep (run.hpp, Cluster). Each generation's simulations are
// divided among the ranks — largest bodies first, each to the rank with the least work so
// far — every rank simulates its share on its own thread pool, and all results are
// exchanged (MPI_Allgatherv) so every rank continues with identical state. Which rank
// simulated a body never changes its result, so the run is bit-identical for any number
// of ranks and threads. MPI is called from the main thread only (MPI_THREAD_FUNNELED).
//
// Several runs at once (run_evolutions) use the ranks differently: rank 0 drives every run
// and keeps the evaluation pool's queue; serve() sends each queued body (its lattice arrays
// and physics) to a free thread of another rank and completes the pool's batch with the
// result; work() on the other ranks simulates what arrives and sends results back as each
// finishes. The results are what evaluate_phenotype() gives, wherever it ran.
#pragma once

#include <string>
#include <vector>

#include "plastivox/evo/run.hpp"

namespace plastivox::evo {

class MpiCluster final : public Cluster {
 public:
  // True when this process was started by mpirun/mpiexec (OpenMPI, MPICH or PMIx
  // environment variables), so MPI must be initialised.
  static bool launched_by_mpirun();

  MpiCluster();            // MPI_Init_thread; throws std::runtime_error on failure
  ~MpiCluster() override;  // MPI_Finalize
  MpiCluster(const MpiCluster&) = delete;
  MpiCluster& operator=(const MpiCluster&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void broadcast(std::string& text) override;
  void barrier() override;
  std::vector<Evaluation> run(const std::vector<const Phenotype*>& batch, const PhysicsDef& physics,
                              int threads) override;
  void serve(EvaluationPool& pool, const std::function<bool()>& finished) override;
  void work(int threads) override;

  // Collective: every rank's bytes, in rank order, on every rank (MPI_Allgatherv). The
  // analysis spreads battery lives over the ranks with it (apps/battery_ranks.cpp).
  std::vector<std::string> allgather(const std::string& mine);
  // Ends every rank (MPI_Abort): for errors on one rank that the others cannot see.
  [[noreturn]] void abort(int code);

 private:
  int rank_ = 0, size_ = 1;
};

// The rank of each job of cost cost[i]: the costliest first (ties by index), each to the rank
// with the least cost assigned so far (ties to the lowest rank). Deterministic.
std::vector<int> assign_by_cost(const std::vector<double>& cost, int ranks);
// assign_by_cost for a batch of bodies, a body's cost 1 + its voxels.
std::vector<int> assign_to_ranks(const std::vector<const Phenotype*>& batch, int ranks);

}  // namespace plastivox::evo
