// CPPN structure checks, lattice inputs and evaluation.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "plastivox/base/names.hpp"
#include "plastivox/evo/cppn.hpp"

namespace plastivox::evo {

const char* to_string(Activation a) {
  static constexpr Named<Activation> kNames[] = {{Activation::kSin, "sin"},
                                                 {Activation::kAbs, "abs"},
                                                 {Activation::kNegAbs, "neg_abs"},
                                                 {Activation::kSquare, "square"},
                                                 {Activation::kNegSquare, "neg_square"},
                                                 {Activation::kSqrtAbs, "sqrt_abs"},
                                                 {Activation::kNegSqrtAbs, "neg_sqrt_abs"},
                                                 {Activation::kIdentity, "identity"}};
  return name_in(kNames, a);
}

double activate(Activation a, double x) {
  switch (a) {
    case Activation::kSin:
      return std::sin(x);
    case Activation::kAbs:
      return std::fabs(x);
    case Activation::kNegAbs:
      return -std::fabs(x);
    case Activation::kSquare:
      return x * x;
    case Activation::kNegSquare:
      return -(x * x);
    case Activation::kSqrtAbs:
      return std::sqrt(std::fabs(x));
    case Activation::kNegSqrtAbs:
      return -std::sqrt(std::fabs(x));
    case Activation::kIdentity:
      return x;
  }
  return x;
}

bool Cppn::operator==(const Cppn& o) const {
  if (nodes != o.nodes || links.size() != o.links.size()) return false;
  for (size_t i = 0; i < links.size(); ++i) {
    const CppnLink &a = links[i], &b = o.links[i];
    if (a.source != b.source || a.target != b.target) return false;
    // Bitwise weight equality (so -0.0 and 0.0 differ, as in every hash of the run).
    if (std::memcmp(&a.weight, &b.weight, sizeof(double)) != 0) return false;
  }
  return true;
}

void validate(const Cppn& net) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("cppn: " + what); };
  const int n = net.node_count();
  if (n < kInputCount + 1) fail("fewer nodes than the 5 inputs and the output");
  for (int i = 0; i < n; ++i) {
    const auto code = static_cast<int>(net.nodes[i]);
    const bool fixed = i < kInputCount || i == n - 1;
    if (fixed && net.nodes[i] != Activation::kIdentity)
      fail("node " + std::to_string(i) + " (input or output) must be identity");
    if (!fixed && (code < 0 || code >= kHiddenActivationCount))
      fail("hidden node " + std::to_string(i) + " has activation code " + std::to_string(code));
  }
  for (size_t k = 0; k < net.links.size(); ++k) {
    const CppnLink& l = net.links[k];
    const std::string at = "link " + std::to_string(k);
    if (l.source < 0 || l.source >= n - 1) fail(at + ": source out of range");
    if (l.target < kInputCount || l.target >= n) fail(at + ": target out of range");
    if (l.source >= l.target) fail(at + ": source must precede target (feed-forward)");
    if (!std::isfinite(l.weight) || l.weight < -1.0 || l.weight > 1.0)
      fail(at + ": weight must be finite and in [-1, 1]");
    if (k > 0) {
      const CppnLink& p = net.links[k - 1];
      if (p.target > l.target || (p.target == l.target && p.source >= l.source))
        fail(at + ": links not sorted by (target, source) or duplicated");
    }
  }
}

CppnInputs lattice_inputs(int nx, int ny, int nz) {
  CppnInputs in;
  in.sites = nx * ny * nz;
  for (auto& v : in.values) v.assign(in.sites, 0.0);
  auto rescale = [](int i, int n) { return n > 1 ? 2.0 * i / (n - 1) - 1.0 : 0.0; };
  double dmin = std::numeric_limits<double>::infinity(), dmax = 0.0;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const int s = x + nx * (y + ny * z);
        const double cx = rescale(x, nx), cy = rescale(y, ny), cz = rescale(z, nz);
        const double d = std::sqrt(cx * cx + cy * cy + cz * cz);
        in.values[0][s] = cx;
        in.values[1][s] = cy;
        in.values[2][s] = cz;
        in.values[3][s] = d;
        in.values[4][s] = 1.0;
        dmin = std::min(dmin, d);
        dmax = std::max(dmax, d);
      }
  for (double& d : in.values[3]) d = dmax > dmin ? 2.0 * (d - dmin) / (dmax - dmin) - 1.0 : 0.0;
  return in;
}

void evaluate(const Cppn& net, const CppnInputs& in, std::vector<double>& out,
              std::vector<double>& scratch) {
  const int n = net.node_count(), sites = in.sites;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  scratch.resize(static_cast<size_t>(n) * sites);
  auto value = [&](int node) { return scratch.data() + static_cast<size_t>(node) * sites; };
  for (int i = 0; i < kInputCount; ++i)
    std::copy(in.values[i].begin(), in.values[i].end(), value(i));
  size_t k = 0;  // links are sorted by target: walk them once
  for (int node = kInputCount; node < n; ++node) {
    double* acc = value(node);
    std::fill(acc, acc + sites, 0.0);
    // Sum the weighted inputs. |w| <= 1 and finite inputs keep each product finite; a NaN
    // input stays NaN (quiet NaN arithmetic raises no exception).
    for (; k < net.links.size() && net.links[k].target == node; ++k) {
      const double w = net.links[k].weight;
      const double* src = value(net.links[k].source);
      for (int s = 0; s < sites; ++s) acc[s] += w * src[s];
    }
    const Activation a = net.nodes[node];
    for (int s = 0; s < sites; ++s) {
      if (!std::isfinite(acc[s])) {
        acc[s] = nan;
        continue;
      }
      const double v = activate(a, acc[s]);
      acc[s] = std::isfinite(v) ? v : nan;
    }
  }
  const double* o = value(n - 1);
  out.assign(o, o + sites);
}

std::vector<double> evaluate(const Cppn& net, const CppnInputs& in) {
  std::vector<double> out, scratch;
  evaluate(net, in, out, scratch);
  return out;
}

}  // namespace plastivox::evo
