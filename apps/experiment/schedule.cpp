// The schedule simulator: list scheduling per generation (kRunByRun) and an event-driven
// replay of the shared queue (kPool).
#include "schedule.hpp"

#include <algorithm>
#include <numeric>
#include <queue>
#include <tuple>

namespace plastivox::experiment {
namespace {

// Makespan of `jobs` (in claim order) on `threads` threads that each take the next job
// when free: the thread pool's dynamic claiming (base/parallel.cpp parallel_for).
double list_schedule(const std::vector<const Job*>& jobs, int threads) {
  std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
  for (int t = 0; t < threads; ++t) free_at.push(0.0);
  double end = 0;
  for (const Job* j : jobs) {
    const double start = free_at.top();
    free_at.pop();
    free_at.push(start + j->seconds);
    end = std::max(end, start + j->seconds);
  }
  return end;
}

// One generation under kRunByRun: ranks by least voxels so far, then threads per rank.
double run_by_run_generation(const std::vector<Job>& jobs, const Layout& layout) {
  std::vector<size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return jobs[a].voxels > jobs[b].voxels; });
  std::vector<double> load(layout.ranks, 0.0);
  std::vector<std::vector<const Job*>> share(layout.ranks);
  for (size_t i : order) {
    const auto r = static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[r] += 1 + jobs[i].voxels;
    share[r].push_back(&jobs[i]);  // already in each rank's own largest-first order
  }
  double end = 0;
  for (const auto& s : share) end = std::max(end, list_schedule(s, layout.threads));
  return end;
}

ScheduleResult run_by_run(const Workload& w, const Layout& layout) {
  ScheduleResult res;
  for (int r = 0; r < w.runs; ++r)
    for (int g = 0; g < w.generations; ++g) {
      const std::vector<Job> jobs = w.jobs(r, g);
      res.wall_seconds += w.seconds_between_generations + run_by_run_generation(jobs, layout);
      for (const Job& j : jobs) res.busy_seconds += j.seconds;
      res.simulations += static_cast<int64_t>(jobs.size());
    }
  return res;
}

ScheduleResult pool(const Workload& w, const Layout& layout) {
  ScheduleResult res;
  // Waiting candidates: longest expected first, then submission order.
  struct Ready {
    double key;
    int64_t seq;
    double seconds;
    int run;
    bool operator<(const Ready& o) const {  // priority_queue pops the largest
      return std::tie(key, o.seq) < std::tie(o.key, seq);
    }
  };
  // Events: a candidate finishing (kind 0) or a run submitting a generation (kind 1).
  using Event = std::tuple<double, int, int>;  // time, kind, run
  std::priority_queue<Ready> ready;
  std::priority_queue<Event, std::vector<Event>, std::greater<>> events;
  std::vector<int> generation(w.runs, 0);
  std::vector<int64_t> remaining(w.runs, 0);
  int64_t seq = 0;
  for (int r = 0; r < w.runs; ++r)
    if (w.generations > 0) events.emplace(w.seconds_between_generations, 1, r);
  int idle = layout.cores();
  double now = 0;
  while (!events.empty()) {
    // Every event of this instant first (runs submitting together compete fairly), then
    // the free cores take the longest waiting candidates.
    now = std::get<0>(events.top());
    while (!events.empty() && std::get<0>(events.top()) == now) {
      const auto [t, kind, r] = events.top();
      events.pop();
      if (kind == 0) {
        ++idle;
        if (--remaining[r] == 0 && ++generation[r] < w.generations)
          events.emplace(now + w.seconds_between_generations, 1, r);
        continue;
      }
      const std::vector<Job> jobs = w.jobs(r, generation[r]);
      for (const Job& j : jobs) {
        ready.push({j.voxels * j.steps, seq++, j.seconds, r});
        res.busy_seconds += j.seconds;
      }
      res.simulations += static_cast<int64_t>(jobs.size());
      remaining[r] = static_cast<int64_t>(jobs.size());
      if (jobs.empty() && ++generation[r] < w.generations)  // all cached: straight on
        events.emplace(now + w.seconds_between_generations, 1, r);
    }
    for (; idle > 0 && !ready.empty(); --idle) {
      events.emplace(now + ready.top().seconds, 0, ready.top().run);
      ready.pop();
    }
  }
  res.wall_seconds = now;
  return res;
}

}  // namespace

ScheduleResult simulate_schedule(const Workload& workload, const Layout& layout, Policy policy) {
  const Layout l{std::max(1, layout.ranks), std::max(1, layout.threads)};
  ScheduleResult res = policy == Policy::kPool ? pool(workload, l) : run_by_run(workload, l);
  const double capacity = static_cast<double>(l.cores()) * res.wall_seconds;
  res.utilization = capacity > 0 ? res.busy_seconds / capacity : 0;
  return res;
}

}  // namespace plastivox::experiment
