// How many champions a comparison needs (docs/analysis.md): the coverage of the study's 95 %
// percentile-bootstrap interval of a mean, and the power of its two-sample bootstrap test,
// on synthetic normal and exponential samples of n values, printed as the Markdown table of
// the docs. kMinBootstrapN (plastivox/analysis/bootstrap_coverage.hpp) is read from it.
//
//   ./build/bench/bootstrap_coverage [--trials 4000] [--resamples 2000] [--power-trials 1000]
//
// A plain program (not Google Benchmark): it measures statistics, not speed. The sample sizes
// run two at a time on threads; each number depends only on the options, never on the threads.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "plastivox/analysis/bootstrap_coverage.hpp"

namespace {

using plastivox::analysis::CoverageOptions;
using plastivox::analysis::SyntheticPopulation;

struct Row {
  int n = 0;
  double normal = 0, gamma4 = 0, exponential = 0;  // coverage of the 95 % interval
  double power = 0, size = 0;  // the test at a shift of 1 sd, and under the null
};

int positive(const char* flag, const char* value) {
  char* end = nullptr;
  const long v = std::strtol(value, &end, 10);
  if (*end != '\0' || v < 1) {
    std::fprintf(stderr, "bootstrap_coverage: %s expects a positive integer, got '%s'\n", flag,
                 value);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  CoverageOptions ci, test;
  ci.trials = 4000;
  test.trials = 1000;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--trials") && has_value) {
      ci.trials = positive(argv[i], argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--power-trials") && has_value) {
      test.trials = positive(argv[i], argv[i + 1]);
    } else if (!std::strcmp(argv[i], "--resamples") && has_value) {
      ci.resamples = test.resamples = positive(argv[i], argv[i + 1]);
    } else {
      std::fprintf(stderr,
                   "usage: bootstrap_coverage [--trials N] [--power-trials N] [--resamples B]\n");
      return 2;
    }
    ++i;
  }
  const std::vector<int> ns = {2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 25, 30, 40, 50, 60, 80, 100};
  std::vector<Row> rows(ns.size());
  const auto measure = [&](size_t k) {
    Row& r = rows[k];
    r.n = ns[k];
    r.normal = ci_coverage(SyntheticPopulation::kNormal, r.n, ci);
    r.gamma4 = ci_coverage(SyntheticPopulation::kGamma4, r.n, ci);
    r.exponential = ci_coverage(SyntheticPopulation::kExponential, r.n, ci);
    r.power = test_power(SyntheticPopulation::kNormal, r.n, 1.0, 3, test);
    r.size = test_power(SyntheticPopulation::kNormal, r.n, 0.0, 3, test);
  };
  std::vector<std::thread> workers;
  for (size_t start = 0; start < 2; ++start)
    workers.emplace_back([&, start] {
      for (size_t k = start; k < ns.size(); k += 2) measure(k);
    });
  for (std::thread& w : workers) w.join();

  std::printf("%d trials per interval, %d per test, %d resamples each\n\n", ci.trials, test.trials,
              ci.resamples);
  std::printf(
      "| n | coverage: normal | gamma-4 (skew 1) | exponential (skew 2) | power, shift 1 sd | "
      "false positives |\n|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %d | %.1f %% | %.1f %% | %.1f %% | %.1f %% | %.1f %% |\n", r.n, 100 * r.normal,
                100 * r.gamma4, 100 * r.exponential, 100 * r.power, 100 * r.size);
  return 0;
}
