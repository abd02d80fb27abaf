// CMA-ES, the covariance matrix adaptation evolution strategy (Hansen, "The CMA Evolution
// Strategy: A Tutorial", arXiv:1604.00772; docs/evolution.md, "CMA-ES"), for continuous
// genomes. Plain state and three pure functions, so a checkpoint holds everything and a
// resumed run continues bit for bit:
//   cma_basis(state)        the sampling basis B D of C = B D^2 B^T (Eigen's self-adjoint
//                           solver, single-threaded, deterministic for a given C);
//   cma_sample(state, ...)  x = m + sigma B D z, z drawn from the caller's keyed stream;
//   cma_update(state, ...)  the tutorial's update from the mu best samples, best first.
// Every sum runs in a fixed order in plain loops, so the bits depend on nothing but the inputs.
//
// Full or separable covariance: the full matrix learns correlations but costs O(n^2) memory,
// an O(n^3) eigendecomposition a generation, and its learning rates (c_1 ~ 2/n^2) make it slow
// to adapt in high dimension. Above kCmaFullMaxDimension the search uses sep-CMA-ES (Ros &
// Hansen 2008): C diagonal, learning rates scaled by (n + 2) / 3, O(n) a sample.
#pragma once

#include <vector>

#include "plastivox/evo/rng.hpp"

namespace plastivox::evo {

constexpr int kCmaFullMaxDimension = 200;
constexpr int kCmaFullLimit = 2000;  // a full covariance asked for beyond this is refused

// The default number of samples a generation: 4 + floor(3 ln n) (the tutorial's).
int cma_default_lambda(int n);

struct CmaState {
  std::vector<double> mean;     // m, the distribution's centre
  std::vector<double> p_sigma;  // the conjugate evolution path (step-size control)
  std::vector<double> p_c;      // the evolution path (rank-one update)
  std::vector<double> cov;      // C: n*n row-major (full), or its diagonal, n (separable)
  double sigma = 0;             // the step size
  int updates = 0;              // generations folded in so far
  bool separable = false;
  int dimension() const { return static_cast<int>(mean.size()); }
  bool operator==(const CmaState&) const = default;
};

// m = x0, C = I, paths 0. separable as the dimension rule says unless forced.
CmaState cma_start(const std::vector<double>& x0, double sigma0, bool separable);

struct CmaBasis {
  std::vector<double> b;  // n*n row-major eigenvectors in columns (full); empty when separable
  std::vector<double> d;  // sqrt of C's eigenvalues (full) or of its diagonal (separable)
};
CmaBasis cma_basis(const CmaState& s);

// One sample: n standard normals from rng, in index order.
std::vector<double> cma_sample(const CmaState& s, const CmaBasis& basis, Rng& rng);

// Moves m, sigma, C and the paths. best: the mu = floor(lambda / 2) best samples of this
// generation, best first (the caller's ranking; ties must already be broken).
void cma_update(CmaState& s, const CmaBasis& basis,
                const std::vector<const std::vector<double>*>& best, int lambda);

}  // namespace plastivox::evo
