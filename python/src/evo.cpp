// Evolution for Python: read a results file (read_results) and run or resume an evolution
// (evolve), the same run as `plastivox evolve`. The run releases the GIL; the generation
// callback takes it back, calls Python and checks for Ctrl-C, which stops the run at the
// next checkpoint (resumable).
#include <atomic>
#include <cmath>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"

namespace plastivox::py {
namespace {

struct PyResults {
  evo::ResultsFile file;
  std::string path;
};

pyb::dict provenance_dict(const Provenance& p) {
  pyb::dict d;
  for_each_field(p, [&](const char* name, const auto& v) { d[name] = v; });
  return d;
}

PyRobot champion(const PyResults& r, int generation) {
  const evo::RunState& run = r.file.state;
  const evo::ChampionRecord& c = evo::champion_at(run, generation, r.path);
  PyRobot out;
  out.def = evo::champion_robot(c, generation < 0 ? run.generations_done : generation);
  out.physics = run.config.physics;
  out.source = r.path;
  return out;
}

// Per generation: the best fitness, and the mean over the population members that were
// simulated to the end (NaN when none was).
pyb::tuple fitness_curves(const PyResults& r) {
  const auto& history = r.file.state.history;
  std::vector<double> best(history.size()), mean(history.size());
  for (size_t g = 0; g < history.size(); ++g) {
    const evo::GenerationRecord& h = history[g];
    best[g] = h.best_fitness;
    double sum = 0;
    int count = 0;
    for (size_t i = 0; i < h.fitness.size(); ++i) {
      if (h.status[i] != static_cast<uint8_t>(evo::EvalStatus::kOk)) continue;
      sum += h.fitness[i];
      ++count;
    }
    mean[g] = count > 0 ? sum / count : std::nan("");
  }
  return pyb::make_tuple(to_array(best), to_array(mean));
}

pyb::dict progress_dict(const evo::RunProgress& p) {
  pyb::dict d;
  d["generation"] = p.generations_done;
  d["generations"] = p.generations_total;
  d["best_fitness"] = p.stats.best_fitness;
  d["champion_id"] = p.stats.champion_id;
  d["created"] = p.stats.created;
  d["simulated"] = p.stats.simulated;
  d["cache_hits"] = p.stats.cache_hits;
  d["invalid"] = p.stats.invalid;
  d["unstable"] = p.stats.unstable;
  d["sank"] = p.stats.sank;  // of the simulated: sank through the floor (also unstable by default)
  d["wall_seconds"] = p.stats.wall_seconds;
  d["checkpointed"] = p.checkpointed;
  d["eta_seconds"] = p.eta_seconds;
  return d;
}

const char* outcome_name(evo::RunOutcome o) {
  switch (o) {
    case evo::RunOutcome::kFinished:
      return "finished";
    case evo::RunOutcome::kAlreadyFinished:
      return "already-finished";
    case evo::RunOutcome::kStopped:
      return "stopped";
  }
  return "?";
}

// config_text: a JSON config (from a dict) or empty with config_path set.
pyb::dict evolve(const std::string& config_text, const std::string& config_path,
                 const std::string& out, int threads, int stop_after,
                 const std::optional<pyb::function>& on_generation,
                 const std::optional<pyb::function>& on_message) {
  const evo::EvolveConfig config = config_path.empty() ? evo::parse_config(config_text, "config")
                                                       : evo::read_config_file(config_path);
  if (threads < -1) throw std::invalid_argument("threads: must be >= 0 (0: all cores)");
  std::atomic<bool> stop{false};
  // A Python exception (the callback's, or KeyboardInterrupt) waits here until the run
  // has checkpointed and returned.
  std::optional<pyb::error_already_set> pending;
  evo::RunOptions opt;
  opt.threads = threads;
  opt.stop_after = stop_after;
  opt.stop_requested = &stop;
  opt.on_generation = [&](const evo::RunProgress& p) {
    pyb::gil_scoped_acquire locked;
    if (pending) return;
    try {
      if (on_generation) (*on_generation)(progress_dict(p));
      if (PyErr_CheckSignals() != 0) throw pyb::error_already_set();
    } catch (pyb::error_already_set& e) {
      pending.emplace(std::move(e));
      stop = true;
    }
  };
  opt.on_message = [&](const std::string& line) {
    if (!on_message) return;
    pyb::gil_scoped_acquire locked;
    if (pending) return;
    try {
      (*on_message)(line);
    } catch (pyb::error_already_set& e) {
      pending.emplace(std::move(e));
      stop = true;
    }
  };
  evo::RunReport report;
  {
    pyb::gil_scoped_release unlocked;
    report = evo::run_evolution(config, out, opt);
  }
  if (pending) {
    pending->restore();
    throw pyb::error_already_set();
  }
  pyb::dict d;
  d["outcome"] = outcome_name(report.outcome);
  d["resumed_from"] = report.resumed_from;
  d["generations_done"] = report.generations_done;
  d["content_digest"] = report.content_digest;
  d["threads"] = report.threads;
  return d;
}

}  // namespace

void bind_evo(pyb::module_& m) {
  pyb::class_<PyResults>(m, "Results")
      .def_property_readonly("path", [](const PyResults& r) { return r.path; })
      .def_property_readonly(
          "treatment", [](const PyResults& r) { return to_string(r.file.state.config.treatment); })
      .def_property_readonly("seed", [](const PyResults& r) { return r.file.state.config.seed; })
      .def_property_readonly("generations_done",
                             [](const PyResults& r) { return r.file.state.generations_done; })
      .def_property_readonly("generations",
                             [](const PyResults& r) { return r.file.state.config.generations; })
      .def_property_readonly("finished", [](const PyResults& r) { return r.file.state.finished(); })
      .def_property_readonly(
          "config_json", [](const PyResults& r) { return r.file.state.config.canonical_json(); })
      .def_property_readonly("content_digest",
                             [](const PyResults& r) { return r.file.content_digest; })
      .def_property_readonly("provenance",
                             [](const PyResults& r) { return provenance_dict(r.file.provenance); })
      .def("champion", &champion, pyb::arg("generation") = -1)
      .def("fitness_curves", &fitness_curves);
  m.def(
      "read_results",
      [](const std::string& path) {
        PyResults r;
        r.path = path;
        r.file = evo::read_results(path);  // with the GIL: HDF5 is not thread-safe
        return r;
      },
      pyb::arg("path"));
  m.def("evolve", &evolve, pyb::arg("config_text"), pyb::arg("config_path"), pyb::arg("out"),
        pyb::arg("threads"), pyb::arg("stop_after"), pyb::arg("on_generation"),
        pyb::arg("on_message"));
  m.def("default_config", [] { return evo::default_config_text(); });
}

}  // namespace plastivox::py
