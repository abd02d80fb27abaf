// CMA-ES (Hansen's tutorial, arXiv:1604.00772, "A.2 Summary" with its default parameters;
// positive recombination weights only) and sep-CMA-ES (Ros & Hansen 2008).
#include "plastivox/evo/cma.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plastivox::evo {
namespace {

// The strategy's constants for dimension n and lambda samples (tutorial, Table 1).
struct Params {
  int n = 0, mu = 0;
  std::vector<double> w;  // mu recombination weights, decreasing, summing to 1
  double mu_eff = 0, c_sigma = 0, d_sigma = 0, c_c = 0, c_1 = 0, c_mu = 0, chi_n = 0;
};

Params params(int n, int lambda, bool separable) {
  Params p;
  p.n = n;
  p.mu = lambda / 2;
  double sum = 0;
  for (int i = 1; i <= p.mu; ++i) {
    p.w.push_back(std::log((lambda + 1) / 2.0) - std::log(static_cast<double>(i)));
    sum += p.w.back();
  }
  double sq = 0;
  for (double& wi : p.w) {
    wi /= sum;
    sq += wi * wi;
  }
  p.mu_eff = 1 / sq;
  const double dn = n;
  p.c_sigma = (p.mu_eff + 2) / (dn + p.mu_eff + 5);
  p.d_sigma = 1 + 2 * std::max(0.0, std::sqrt((p.mu_eff - 1) / (dn + 1)) - 1) + p.c_sigma;
  p.c_c = (4 + p.mu_eff / dn) / (dn + 4 + 2 * p.mu_eff / dn);
  p.c_1 = 2 / ((dn + 1.3) * (dn + 1.3) + p.mu_eff);
  p.c_mu =
      std::min(1 - p.c_1, 2 * (p.mu_eff - 2 + 1 / p.mu_eff) / ((dn + 2) * (dn + 2) + p.mu_eff));
  if (separable) {  // Ros & Hansen: a diagonal C can learn (n + 2) / 3 times faster
    const double f = (dn + 2) / 3;
    p.c_1 = std::min(1.0, p.c_1 * f);
    p.c_mu = std::min(1 - p.c_1, p.c_mu * f);
  }
  p.chi_n = std::sqrt(dn) * (1 - 1 / (4 * dn) + 1 / (21 * dn * dn));  // E||N(0, I)||
  return p;
}

double norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

}  // namespace

int cma_default_lambda(int n) {
  return 4 + static_cast<int>(std::floor(3 * std::log(static_cast<double>(std::max(n, 1)))));
}

CmaState cma_start(const std::vector<double>& x0, double sigma0, bool separable) {
  const size_t n = x0.size();
  if (n == 0) throw std::invalid_argument("cma-es: the genome has no numbers to search");
  CmaState s;
  s.mean = x0;
  s.p_sigma.assign(n, 0.0);
  s.p_c.assign(n, 0.0);
  s.sigma = sigma0;
  s.separable = separable;
  if (separable) {
    s.cov.assign(n, 1.0);
  } else {
    s.cov.assign(n * n, 0.0);
    for (size_t i = 0; i < n; ++i) s.cov[i * n + i] = 1.0;
  }
  return s;
}

CmaBasis cma_basis(const CmaState& s) {
  const int n = s.dimension();
  CmaBasis out;
  out.d.resize(n);
  if (s.separable) {
    for (int i = 0; i < n; ++i) out.d[i] = std::sqrt(std::max(s.cov[i], 0.0));
    return out;
  }
  Eigen::MatrixXd c(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) c(i, j) = s.cov[static_cast<size_t>(i) * n + j];
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(c);
  if (eig.info() != Eigen::Success) throw std::runtime_error("cma-es: eigendecomposition failed");
  // Rounding can leave an eigenvalue at or below zero: floor it far below the largest.
  const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  out.b.resize(static_cast<size_t>(n) * n);
  for (int i = 0; i < n; ++i) {
    out.d[i] = std::sqrt(std::max(eig.eigenvalues()(i), top * 1e-20));
    for (int j = 0; j < n; ++j) out.b[static_cast<size_t>(i) * n + j] = eig.eigenvectors()(i, j);
  }
  return out;
}

std::vector<double> cma_sample(const CmaState& s, const CmaBasis& basis, Rng& rng) {
  const int n = s.dimension();
  std::vector<double> z(n);
  for (double& v : z) v = rng.normal();
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) {
    double y = 0;  // (B D z)_i
    if (s.separable) {
      y = basis.d[i] * z[i];
    } else {
      for (int j = 0; j < n; ++j) y += basis.b[static_cast<size_t>(i) * n + j] * basis.d[j] * z[j];
    }
    x[i] = s.mean[i] + s.sigma * y;
  }
  return x;
}

void cma_update(CmaState& s, const CmaBasis& basis,
                const std::vector<const std::vector<double>*>& best, int lambda) {
  const int n = s.dimension();
  const Params p = params(n, lambda, s.separable);
  if (static_cast<int>(best.size()) != p.mu)
    throw std::logic_error("cma-es: update needs the mu best samples");
  // y_i = (x_i - m) / sigma, and their weighted mean y_w.
  std::vector<std::vector<double>> y(p.mu, std::vector<double>(n));
  std::vector<double> y_w(n, 0.0);
  for (int k = 0; k < p.mu; ++k)
    for (int i = 0; i < n; ++i) {
      y[k][i] = ((*best[k])[i] - s.mean[i]) / s.sigma;
      y_w[i] += p.w[k] * y[k][i];
    }
  for (int i = 0; i < n; ++i) s.mean[i] += s.sigma * y_w[i];

  // C^(-1/2) y_w = B D^-1 B^T y_w.
  std::vector<double> white(n);
  if (s.separable) {
    for (int i = 0; i < n; ++i) white[i] = y_w[i] / basis.d[i];
  } else {
    std::vector<double> t(n, 0.0);  // D^-1 B^T y_w
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) t[j] += basis.b[static_cast<size_t>(i) * n + j] * y_w[i];
      t[j] /= basis.d[j];
    }
    for (int i = 0; i < n; ++i) {
      white[i] = 0;
      for (int j = 0; j < n; ++j) white[i] += basis.b[static_cast<size_t>(i) * n + j] * t[j];
    }
  }
  const double ks = std::sqrt(p.c_sigma * (2 - p.c_sigma) * p.mu_eff);
  for (int i = 0; i < n; ++i) s.p_sigma[i] = (1 - p.c_sigma) * s.p_sigma[i] + ks * white[i];
  s.updates += 1;
  const double ps = norm(s.p_sigma);
  const double fade = std::sqrt(1 - std::pow(1 - p.c_sigma, 2.0 * s.updates));
  const bool h_sigma = ps / fade < (1.4 + 2 / (n + 1.0)) * p.chi_n;
  const double kc = std::sqrt(p.c_c * (2 - p.c_c) * p.mu_eff);
  for (int i = 0; i < n; ++i) s.p_c[i] = (1 - p.c_c) * s.p_c[i] + (h_sigma ? kc * y_w[i] : 0.0);
  const double delta = h_sigma ? 0.0 : p.c_c * (2 - p.c_c);
  const double keep = 1 + p.c_1 * delta - p.c_1 - p.c_mu;  // the weights sum to 1
  const auto rank_mu = [&](int i, int j) {
    double r = 0;
    for (int k = 0; k < p.mu; ++k) r += p.w[k] * y[k][i] * y[k][j];
    return r;
  };
  if (s.separable) {
    for (int i = 0; i < n; ++i)
      s.cov[i] = keep * s.cov[i] + p.c_1 * s.p_c[i] * s.p_c[i] + p.c_mu * rank_mu(i, i);
  } else {
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j) {  // the upper triangle, mirrored: C stays exactly symmetric
        const size_t ij = static_cast<size_t>(i) * n + j;
        s.cov[ij] = keep * s.cov[ij] + p.c_1 * s.p_c[i] * s.p_c[j] + p.c_mu * rank_mu(i, j);
        s.cov[static_cast<size_t>(j) * n + i] = s.cov[ij];
      }
  }
  s.sigma *= std::exp(p.c_sigma / p.d_sigma * (ps / p.chi_n - 1));
}

}  // namespace plastivox::evo
