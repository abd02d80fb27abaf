// The schedule simulator: list scheduling per generation (kRunByRun) and an event-driven
// replay of the shared queue (kPool).
#include "schedule.hpp"

#include <algorithm>
#include <cmath>
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

ScheduleResult replay(const Workload& w, const Layout& l, Policy policy) {
  return policy == Policy::kPool ? pool(w, l) : run_by_run(w, l);
}

// `a` + (a - b) x k, field by field: a replay extended by k more times the difference
// between two replays.
ScheduleResult extend(const ScheduleResult& a, const ScheduleResult& b, double k) {
  ScheduleResult r;
  r.wall_seconds = a.wall_seconds + (a.wall_seconds - b.wall_seconds) * k;
  r.busy_seconds = a.busy_seconds + (a.busy_seconds - b.busy_seconds) * k;
  r.simulations =
      a.simulations +
      static_cast<int64_t>(std::llround(static_cast<double>(a.simulations - b.simulations) * k));
  return r;
}

}  // namespace

ScheduleResult simulate_schedule(const Workload& workload, const Layout& layout, Policy policy,
                                 int64_t max_replayed) {
  const int64_t kReplayJobs = std::max<int64_t>(max_replayed, 64);
  Layout l{std::max(1, layout.ranks), std::max(1, layout.threads)};
  const int64_t per_generation =
      workload.generations > 1
          ? static_cast<int64_t>(workload.jobs(0, 1).size())
          : (workload.generations == 1 ? static_cast<int64_t>(workload.jobs(0, 0).size()) : 0);
  Workload w = workload;
  // Fewer runs: runs are alike, so a share of them on the same share of the cores (the pool)
  // or one after another (run by run) takes the same time per run.
  double run_scale = 1;
  const int64_t round = per_generation * w.runs;  // one generation of every run
  if (round > kReplayJobs / 4 && w.runs > 1) {
    w.runs = static_cast<int>(
        std::max<int64_t>(1, kReplayJobs / 4 / std::max<int64_t>(1, per_generation)));
    run_scale = static_cast<double>(workload.runs) / w.runs;
    if (policy == Policy::kPool)
      l = {1, static_cast<int>(std::max<int64_t>(1, std::llround(l.cores() / run_scale)))};
  }
  // Fewer generations: after the first few, every generation costs the same in expectation,
  // so the replay of g generations and of g / 2 give the cost of one more.
  ScheduleResult res;
  const int64_t g =
      std::max<int64_t>(8, kReplayJobs / std::max<int64_t>(1, per_generation * w.runs));
  if (w.generations > g) {
    w.generations = static_cast<int>(g);
    const ScheduleResult full = replay(w, l, policy);
    w.generations = static_cast<int>(g / 2);
    const ScheduleResult half = replay(w, l, policy);
    res = extend(full, half, static_cast<double>(workload.generations - g) / (g - g / 2));
  } else {
    res = replay(w, l, policy);
  }
  if (policy == Policy::kRunByRun) res.wall_seconds *= run_scale;
  res.busy_seconds *= run_scale;
  res.simulations =
      static_cast<int64_t>(std::llround(static_cast<double>(res.simulations) * run_scale));
  const double capacity = static_cast<double>(layout.cores()) * res.wall_seconds;
  res.utilization = capacity > 0 ? std::min(1.0, res.busy_seconds / capacity) : 0;
  return res;
}

}  // namespace plastivox::experiment
