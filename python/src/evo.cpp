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
#include "plastivox/evo/cma_body.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/genome.hpp"
#include "plastivox/evo/map_elites.hpp"
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

// A CPPN genome as Python reads and sets it (docs/python.md, "Genomes"): per network
// (geometry, stiffness, development, phase) a dict of `activation` (one name per node, in
// topological order: the five inputs, hidden nodes, the output), `source`, `target` (int
// arrays, node indices) and `weight` (float array), one entry per link sorted by (target,
// source); and `controller`, the controller's weights (empty under the sine).
pyb::dict genome_to_python(const evo::Genome& g) {
  pyb::dict d;
  for (int n = 0; n < evo::kNetworkCount; ++n) {
    const evo::Cppn& net = g.nets[n];
    pyb::list act;
    for (evo::Activation a : net.nodes) act.append(evo::to_string(a));
    pyb::array_t<int32_t> src(static_cast<pyb::ssize_t>(net.links.size()));
    pyb::array_t<int32_t> dst(static_cast<pyb::ssize_t>(net.links.size()));
    std::vector<double> w;
    for (size_t k = 0; k < net.links.size(); ++k) {
      src.mutable_at(k) = net.links[k].source;
      dst.mutable_at(k) = net.links[k].target;
      w.push_back(net.links[k].weight);
    }
    pyb::dict nd;
    nd["activation"] = act;
    nd["source"] = src;
    nd["target"] = dst;
    nd["weight"] = to_array(w);
    d[evo::to_string(static_cast<evo::Network>(n))] = nd;
  }
  d["controller"] = to_array(g.controller);
  return d;
}

// The inverse, checked: the keys, one activation name a node, link arrays of one length, the
// networks' invariants (evo::validate: layout, order, ranges, weights in [-1, 1]) and
// `controller_count` weights. std::invalid_argument naming `what` and the field.
evo::Genome genome_from_python(const pyb::handle& given, size_t controller_count,
                               const std::string& what) {
  if (!pyb::isinstance<pyb::dict>(given))
    throw std::invalid_argument(what + ": expected a dict (ask(genomes=True) gives one)");
  const pyb::dict d = pyb::reinterpret_borrow<pyb::dict>(given);
  for (const auto& item : d) {
    const std::string k = pyb::str(item.first);
    bool known = k == "controller";
    for (int n = 0; n < evo::kNetworkCount; ++n)
      known |= k == evo::to_string(static_cast<evo::Network>(n));
    if (!known) throw std::invalid_argument(what + ": unknown key '" + k + "'");
  }
  evo::Genome g;
  for (int n = 0; n < evo::kNetworkCount; ++n) {
    const std::string name = evo::to_string(static_cast<evo::Network>(n));
    const std::string at = what + "." + name;
    if (!d.contains(name)) throw std::invalid_argument(at + ": missing");
    const pyb::object net = d[name.c_str()];
    if (!pyb::isinstance<pyb::dict>(net))
      throw std::invalid_argument(at + ": expected a dict of activation, source, target, weight");
    const pyb::dict nd = pyb::reinterpret_borrow<pyb::dict>(net);
    for (const char* field : {"activation", "source", "target", "weight"})
      if (!nd.contains(field)) throw std::invalid_argument(at + "." + field + ": missing");
    std::vector<std::string> act;
    std::vector<int64_t> src, dst;
    std::vector<double> w;
    try {
      act = nd["activation"].cast<std::vector<std::string>>();
    } catch (const pyb::cast_error&) {
      throw std::invalid_argument(at + ".activation: expected a list of activation names");
    }
    try {
      src = nd["source"].cast<std::vector<int64_t>>();
      dst = nd["target"].cast<std::vector<int64_t>>();
      w = nd["weight"].cast<std::vector<double>>();
    } catch (const pyb::cast_error&) {
      throw std::invalid_argument(at +
                                  ": source and target must be integer arrays, weight a "
                                  "float array");
    }
    if (src.size() != w.size() || dst.size() != w.size())
      throw std::invalid_argument(at + ": source, target and weight must have one length, got " +
                                  std::to_string(src.size()) + ", " + std::to_string(dst.size()) +
                                  ", " + std::to_string(w.size()));
    evo::Cppn& c = g.nets[n];
    for (size_t k = 0; k < act.size(); ++k) {
      int code = -1;
      for (int a = 0; a <= static_cast<int>(evo::Activation::kIdentity); ++a)
        if (act[k] == evo::to_string(static_cast<evo::Activation>(a))) code = a;
      if (code < 0)
        throw std::invalid_argument(at + ".activation[" + std::to_string(k) + "]: '" + act[k] +
                                    "' is unknown (use sin, abs, neg_abs, square, neg_square, "
                                    "sqrt_abs, neg_sqrt_abs; identity for inputs and output)");
      c.nodes.push_back(static_cast<evo::Activation>(code));
    }
    constexpr int64_t kMaxNode = int64_t{1} << 30;
    for (size_t k = 0; k < w.size(); ++k) {
      if (src[k] < 0 || dst[k] < 0 || src[k] > kMaxNode || dst[k] > kMaxNode)
        throw std::invalid_argument(at + ": link " + std::to_string(k) +
                                    " names a node out of range");
      c.links.push_back({static_cast<int>(src[k]), static_cast<int>(dst[k]), w[k]});
    }
    try {
      evo::validate(c);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(at + ": " + e.what());
    }
  }
  if (d.contains("controller")) {
    try {
      g.controller = d["controller"].cast<std::vector<double>>();
    } catch (const pyb::cast_error&) {
      throw std::invalid_argument(what + ".controller: expected a float array");
    }
  }
  if (g.controller.size() != controller_count)
    throw std::invalid_argument(what + ".controller: expected " + std::to_string(controller_count) +
                                " weights, got " + std::to_string(g.controller.size()));
  for (double x : g.controller)
    if (!std::isfinite(x))
      throw std::invalid_argument(what + ".controller: a weight is not finite");
  return g;
}

// The population of the file's last checkpoint, each individual's genome decoded into its
// body under the run's physics (None for an invalid body), with its bookkeeping. With the
// champions (champion()), these are the individuals whose genomes a results file stores.
pyb::list population(const PyResults& r) {
  const evo::RunState& run = r.file.state;
  const evo::Expresser expresser(run.config.expression());
  pyb::list out;
  for (const evo::Individual& ind : run.population) {
    pyb::dict d;
    d["id"] = ind.id;
    d["parent_id"] = ind.parent_id;
    d["age"] = ind.age;
    d["born"] = ind.born;
    d["fitness"] = ind.fitness;
    d["status"] = evo::to_string(ind.status);
    const evo::Phenotype body = run.config.algorithm == evo::Algorithm::kCmaEs
                                    ? evo::express_vector(run.config, ind.genome.controller)
                                    : expresser.express(ind.genome);
    if (run.config.algorithm == evo::Algorithm::kCmaEs)
      d["genome"] = ind.genome.controller;  // the CMA-ES vector
    if (body.valid) {
      PyRobot robot;
      robot.def = body.robot;
      robot.def.name = "individual-" + std::to_string(ind.id);
      robot.physics = run.config.physics;
      robot.source = r.path;
      d["robot"] = robot;
    } else {
      d["robot"] = pyb::none();
    }
    out.append(d);
  }
  return out;
}

// A MAP-Elites run's archive at the file's last checkpoint (docs/evolution.md, "MAP-Elites"):
// its axes, every elite (cell, bins, descriptors, fitness, ids, its robot under the run's
// physics) and, per generation, the QD score, coverage and evaluations so far.
pyb::dict archive(const PyResults& r) {
  const evo::RunState& run = r.file.state;
  if (run.config.algorithm != evo::Algorithm::kMapElites)
    throw std::invalid_argument(r.path + ": algorithm " +
                                std::string(to_string(run.config.algorithm)) + " keeps no archive");
  const evo::MapElitesSettings& me = run.config.map_elites;
  pyb::dict out;
  pyb::list axes;
  for (const evo::DescriptorAxis& a : me.axes) {
    pyb::dict d;
    d["name"] = to_string(a.what);
    d["bounds"] = pyb::make_tuple(a.lo, a.hi);
    d["bins"] = a.bins;
    axes.append(d);
  }
  out["descriptors"] = axes;
  out["cells"] = me.cells();
  out["qd_offset"] = me.qd_offset;
  const evo::Expresser expresser(run.config.expression());
  pyb::list elites;
  for (const evo::Individual& e : run.archive) {
    pyb::dict d;
    d["cell"] = e.cell;
    d["bins"] = evo::bins_of(me, e.cell);
    d["descriptors"] = e.descriptors;
    d["fitness"] = e.fitness;
    d["id"] = e.id;
    d["parent_id"] = e.parent_id;
    d["born"] = e.born;
    PyRobot robot;
    robot.def = expresser.express(e.genome).robot;
    robot.def.name = "elite-" + std::to_string(e.id);
    robot.physics = run.config.physics;
    robot.source = r.path;
    d["robot"] = robot;
    elites.append(d);
  }
  out["elites"] = elites;
  std::vector<double> qd, coverage, evaluations;
  size_t born = 0;
  for (const evo::GenerationRecord& h : run.history) {
    qd.push_back(h.qd_score);
    coverage.push_back(static_cast<double>(h.filled) / static_cast<double>(me.cells()));
    while (born < run.births.size() &&
           run.births[born].generation <= static_cast<int>(evaluations.size()))
      ++born;
    evaluations.push_back(static_cast<double>(born));
  }
  out["qd_score"] = to_array(qd);
  out["coverage"] = to_array(coverage);
  out["evaluations"] = to_array(evaluations);
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
  d["sim_wall_seconds"] = p.stats.sim_wall_seconds;  // of which simulating (wall)
  d["sim_cpu_seconds"] = p.stats.sim_cpu_seconds;    // the lives' own times, summed
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

// Raised out of a generation whose lives Python did not score (its evaluate callable
// raised): the generation is dropped, never checkpointed; the run stands at its last
// checkpoint.
struct EvaluationAbandoned : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Lives scored by Python: evaluate(robots, vectors) receives a generation's new bodies as
// Robots under the run's physics (and, under CMA-ES, each one's genome vector; None under
// AFPO) and returns one (ok, fitness, failure, sank, final_stiffness)
// per robot: ok False for a life that failed (fitness ignored: the worst), final_stiffness
// one value per voxel (Pa, increasing site order) or None (then a champion's is simulated).
// The Python layer (plastivox.evolve, plastivox.Evolver) makes these from users' numbers
// and Results.
class PythonEvaluations : public evo::Simulations {
 public:
  PythonEvaluations(pyb::function evaluate, std::optional<pyb::error_already_set>& pending)
      : evaluate_(std::move(evaluate)), pending_(pending) {}

  std::vector<evo::Evaluation> run(const std::vector<const evo::Phenotype*>& batch,
                                   const PhysicsDef& physics, int) override {
    if (batch.empty()) return {};  // every new body was invalid or seen before
    pyb::gil_scoped_acquire locked;
    try {
      // Each body's genome: a CMA-ES run's vector, or the CPPN genome as a dict.
      pyb::list robots, vectors;
      for (size_t i = 0; i < batch.size(); ++i) {
        const evo::Phenotype* p = batch[i];
        PyRobot r;
        r.def = p->robot;
        r.physics = physics;
        r.source = "evolution";
        robots.append(pyb::cast(std::move(r)));
        if (!p->vector.empty())
          vectors.append(pyb::cast(p->vector));
        else if (i < genomes_.size())
          vectors.append(genome_to_python(*genomes_[i]));
        else
          vectors.append(pyb::none());
      }
      const pyb::list scored = evaluate_(robots, vectors);
      if (scored.size() != batch.size())
        throw std::invalid_argument("evaluate: expected " + std::to_string(batch.size()) +
                                    " scores, got " + std::to_string(scored.size()));
      std::vector<evo::Evaluation> out(batch.size());
      for (size_t i = 0; i < batch.size(); ++i) {
        const pyb::object set = pyb::reinterpret_borrow<pyb::tuple>(scored[i])[6];
        out[i] = evaluation(*batch[i], scored[i], !set.is_none());
        if (set.is_none()) continue;
        if (i >= genomes_.size() || !batch[i]->vector.empty())
          throw std::invalid_argument("genomes: only a CPPN genome (afpo, map-elites) can be set");
        out[i].edited = genome_from_python(set, genomes_[i]->controller.size(),
                                           "genomes[" + std::to_string(i) + "]");
      }
      genomes_.clear();
      return out;
    } catch (pyb::error_already_set& e) {
      pending_.emplace(std::move(e));
    } catch (const std::exception& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
      pending_.emplace();  // takes the error just set
    }
    throw EvaluationAbandoned("the generation's lives were not scored");
  }

  void genomes(const std::vector<const evo::Genome*>& batch) override { genomes_ = batch; }

 private:
  // set: a genome was set for this body, so a Result's final stiffness (another body's lattice
  // sites) is not taken; the evolver simulates a champion's life again for it.
  static evo::Evaluation evaluation(const evo::Phenotype& p, const pyb::handle& item, bool set) {
    // The 7th, the genome set (or None), is run()'s.
    const auto [ok, fitness, failure, sank, stiffness, vertical, genome] =
        item.cast<std::tuple<bool, double, std::string, bool, std::optional<std::vector<double>>,
                             bool, pyb::object>>();
    (void)genome;
    evo::Evaluation e;
    e.sank = sank;
    e.vertical = vertical;
    if (ok && std::isfinite(fitness)) {
      e.status = evo::EvalStatus::kOk;
      e.fitness = fitness;
    } else {
      e.status = evo::EvalStatus::kUnstable;
      e.failure = failure.empty() ? "the fitness function gave no finite fitness" : failure;
    }
    if (stiffness && !set) {
      if (static_cast<int>(stiffness->size()) != p.robot.voxel_count())
        throw std::invalid_argument("final_stiffness: expected one value per voxel");
      e.final_stiffness.assign(p.robot.sites(), 0.0);
      size_t v = 0;
      for (int site = 0; site < p.robot.sites(); ++site)
        if (p.robot.present[site]) e.final_stiffness[site] = (*stiffness)[v++];
    }
    return e;
  }

  pyb::function evaluate_;
  std::optional<pyb::error_already_set>& pending_;
  std::vector<const evo::Genome*> genomes_;  // the batch's, until run() returns
};

// config_text: a JSON config (from a dict) or empty with config_path set. evaluate, when
// given, scores the lives (PythonEvaluations) and fitness_function names it in the file.
pyb::dict evolve(const std::string& config_text, const std::string& config_path,
                 const std::string& out, int threads, int stop_after,
                 const std::optional<pyb::function>& on_generation,
                 const std::optional<pyb::function>& on_message,
                 const std::optional<pyb::function>& evaluate,
                 const std::string& fitness_function) {
  const evo::EvolveConfig config = config_path.empty() ? evo::parse_config(config_text, "config")
                                                       : evo::read_config_file(config_path);
  // -1: the config's threads, as `plastivox evolve` without --threads.
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
  std::optional<PythonEvaluations> scored;
  if (evaluate) {
    scored.emplace(*evaluate, pending);
    opt.simulations = &*scored;
    opt.fitness_function = "python: " + fitness_function;
  }
  evo::RunReport report;
  try {
    pyb::gil_scoped_release unlocked;
    report = evo::run_evolution(config, out, opt);
  } catch (const EvaluationAbandoned&) {
    // pending holds why
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
      .def("population", &population)
      .def("archive", &archive)
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
        pyb::arg("on_message"), pyb::arg("evaluate") = pyb::none(),
        pyb::arg("fitness_function") = "");
  m.def("default_config", [] { return evo::default_config_text(); });
  // A genome as ask(genomes=True) gives it, checked (ValueError naming `what` and the field).
  m.def(
      "check_genome",
      [](const pyb::handle& genome, size_t controller_count, const std::string& what) {
        genome_from_python(genome, controller_count, what);
      },
      pyb::arg("genome"), pyb::arg("controller_count"), pyb::arg("what"));
  // The body a CPPN genome gives under a config (None when invalid), as the evolver makes it.
  m.def(
      "express_genome",
      [](const std::string& config_text, const std::string& config_path,
         const pyb::handle& genome) -> pyb::object {
        const evo::EvolveConfig config = config_path.empty()
                                             ? evo::parse_config(config_text, "config")
                                             : evo::read_config_file(config_path);
        if (config.algorithm == evo::Algorithm::kCmaEs)
          throw std::invalid_argument("genome: a CMA-ES run's genome is a vector on its body");
        const evo::Genome g = genome_from_python(
            genome, static_cast<size_t>(config.controller_genes.count), "genome");
        const evo::Expresser expresser(config.expression());
        const evo::Phenotype p = expresser.express(g);
        if (!p.valid) return pyb::none();
        PyRobot r;
        r.def = p.robot;
        r.physics = config.physics;
        r.source = "evolution";
        return pyb::cast(std::move(r));
      },
      pyb::arg("config_text"), pyb::arg("config_path"), pyb::arg("genome"));
  // The config's "threads" (what evolve uses when given none), parsed as evolve parses it.
  m.def(
      "config_threads",
      [](const std::string& config_text, const std::string& config_path) {
        return (config_path.empty() ? evo::parse_config(config_text, "config")
                                    : evo::read_config_file(config_path))
            .threads;
      },
      pyb::arg("config_text"), pyb::arg("config_path"));
}

}  // namespace plastivox::py
