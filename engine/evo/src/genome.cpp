#include "plastivox/evo/genome.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "plastivox/base/names.hpp"

namespace plastivox::evo {

const char* to_string(Network n) {
  static constexpr Named<Network> kNames[] = {{Network::kGeometry, "geometry"},
                                              {Network::kStiffness, "stiffness"},
                                              {Network::kDevelopment, "development"},
                                              {Network::kPhase, "phase"}};
  return name_in(kNames, n);
}

Genome random_genome(Rng& rng, const ControllerGenes& genes) {
  Genome g;
  for (Cppn& net : g.nets) net = random_cppn(rng);
  g.controller.resize(genes.count);
  for (double& w : g.controller) w = genes.init_sigma * rng.normal();
  return g;
}

void mutate_controller(std::vector<double>& weights, const ControllerGenes& genes, Rng& rng) {
  bool changed = false;
  for (double& w : weights)
    if (rng.coin(genes.rate)) {
      w += genes.sigma * rng.normal();
      changed = true;
    }
  if (!changed && !weights.empty())
    weights[rng.index(static_cast<int>(weights.size()))] += genes.sigma * rng.normal();
}

namespace {

// A network from its hidden activations and its links; node indices: inputs 0..4 (x, y, z, d,
// bias), hidden nodes from 5 in the order given, the output last.
Cppn hand_built(const std::vector<Activation>& hidden, std::vector<CppnLink> links) {
  Cppn net;
  net.nodes.assign(kInputCount, Activation::kIdentity);
  net.nodes.insert(net.nodes.end(), hidden.begin(), hidden.end());
  net.nodes.push_back(Activation::kIdentity);
  std::sort(links.begin(), links.end(), [](const CppnLink& a, const CppnLink& b) {
    return a.target != b.target ? a.target < b.target : a.source < b.source;
  });
  net.links = std::move(links);
  return net;
}

}  // namespace

Cppn body_plan_geometry(int plan) {
  constexpr int x = 0, y = 1, z = 2, bias = 4;
  using A = Activation;
  // Thresholds are off the lattice values k/n for small n, so no site sits on a boundary.
  switch (plan) {
    case 0: {  // Π: a = |x| - 0.4142 (legs), b = z + 0.0913 (bridge); h5 = |x|, h6 = |a - b|
      const int out = 7;
      return hand_built({A::kAbs, A::kAbs}, {{x, 5, 1.0},
                                             {5, 6, 1.0},
                                             {z, 6, -1.0},
                                             {bias, 6, -0.5055},
                                             {5, out, 0.5},
                                             {z, out, 0.5},
                                             {6, out, 0.5},
                                             {bias, out, -0.16145}});
    }
    case 1: {  // Γ: a = -x - 0.4142 (wall), b = -z - 0.4142 (floor plate); h5 = |a - b|
      const int out = 6;
      return hand_built({A::kAbs}, {{x, 5, -1.0},
                                    {z, 5, 1.0},
                                    {x, out, -0.5},
                                    {z, out, -0.5},
                                    {5, out, 0.5},
                                    {bias, out, -0.4142}});
    }
    case 2: {  // Υ: a = -x - 0.5137 (plate), b = 0.27 - y^2 - z^2 (rod); h5 = y^2, h6 = z^2,
               // h7 = |a - b|
      const int out = 8;
      return hand_built({A::kSquare, A::kSquare, A::kAbs}, {{y, 5, 1.0},
                                                            {z, 6, 1.0},
                                                            {x, 7, -1.0},
                                                            {5, 7, 1.0},
                                                            {6, 7, 1.0},
                                                            {bias, 7, -0.7837},
                                                            {x, out, -0.5},
                                                            {5, out, -0.5},
                                                            {6, out, -0.5},
                                                            {7, out, 0.5},
                                                            {bias, out, -0.12185}});
    }
  }
  throw std::invalid_argument("body_plan_geometry: plan " + std::to_string(plan) +
                              " is not 0 (Π), 1 (Γ) or 2 (Υ)");
}

void validate(const Genome& g) {
  for (int i = 0; i < kNetworkCount; ++i) {
    try {
      validate(g.nets[i]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(to_string(static_cast<Network>(i))) +
                                  " network: " + e.what());
    }
  }
}

}  // namespace plastivox::evo
