// Writing the results file (layout: docs/results-format.md), atomically.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/file_seal.hpp"
#include "plastivox/io/h5_util.hpp"
#include "plastivox/task.hpp"
#include "results_layout.hpp"

namespace plastivox::evo {
namespace layout {

std::string champion_name(size_t k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%06zu", k);
  return buf;
}

Hash128 checkpoint_digest(const RunState& s) {
  Hasher h;
  h.str("plastivox-evolution-checkpoint-v1");
  h.u64(s.cache.size());
  for (const auto& [key, e] : s.cache) {
    h.u64(key.hi);
    h.u64(key.lo);
    h.f64(e.fitness);
    h.u64(static_cast<uint8_t>(e.status));
    h.str(e.failure);
    if (s.config.algorithm == Algorithm::kMapElites) {  // only then: other digests hold
      h.u64(e.measures.measured ? 1 : 0);
      h.f64(e.measures.floor_contact);
      h.f64(e.measures.com_height);
      h.f64(e.measures.development);
    }
  }
  for (const GenerationRecord& g : s.history) {
    h.u64(static_cast<uint64_t>(g.simulated));
    h.u64(static_cast<uint64_t>(g.cache_hits));
  }
  for (const BirthRecord& b : s.births) h.u64(b.simulated);
  return h.finish();
}

}  // namespace layout

namespace {

using h5::Ctx;
using h5::Handle;

// The unit of every fitness in the file: the run's task's (voxel lengths for walk and jump).
const char* fitness_unit(const RunState& s) {
  return task_info(s.config.task).unit;
}

std::vector<hsize_t> lattice_dims(const RobotDef& r) {
  return {static_cast<hsize_t>(r.nz), static_cast<hsize_t>(r.ny), static_cast<hsize_t>(r.nx)};
}

void write_network(const Ctx& c, hid_t group, const Cppn& net) {
  std::vector<uint8_t> act(net.nodes.size());
  for (size_t i = 0; i < act.size(); ++i) act[i] = static_cast<uint8_t>(net.nodes[i]);
  std::vector<int32_t> src, dst;
  std::vector<double> w;
  for (const CppnLink& l : net.links) {
    src.push_back(l.source);
    dst.push_back(l.target);
    w.push_back(l.weight);
  }
  h5::write(c, group, "activation", act);
  h5::write(c, group, "source", src);
  h5::write(c, group, "target", dst);
  h5::write(c, group, "weight", w);
}

void write_phenotype(const Ctx& c, hid_t group, const RobotDef& r) {
  const auto dims = lattice_dims(r);
  h5::write(c, group, "present", r.present, dims);
  h5::write(c, group, "stiffness", r.stiffness, dims);
  h5::write(c, group, "dev_rate", r.dev_rate, dims);
  h5::write(c, group, "phase", r.phase, dims);
  for (const auto& [name, units] :
       {std::pair{"stiffness", "Pa"}, {"dev_rate", "1/s"}, {"phase", "cycles"}})
    h5::write_units(c, group, name, units);
}

void write_root_attributes(const Ctx& c, hid_t root, const RunState& s, const Provenance& p) {
  h5::write_attr(c, root, "format", std::string(layout::kFormat));
  h5::write_attr(c, root, "format_version", int64_t{kResultsFormatVersion});
  h5::write_attr(c, root, "config", s.config.canonical_json());
  h5::write_attr(c, root, "resolved_physics", resolved_physics_json(s.config.physics));
  h5::write_attr(c, root, "sunk_lives",
                 std::string(s.config.physics.sinking_invalid ? "invalid" : "scored"));
  h5::write_attr_u64(c, root, "seed", s.config.seed);
  h5::write_attr(c, root, "treatment", std::string(to_string(s.config.treatment)));
  h5::write_attr(c, root, "task", std::string(to_string(s.config.task)));
  h5::write_attr(c, root, "fitness_unit", std::string(fitness_unit(s)));
  h5::write_attr(c, root, "population", int64_t{s.config.population});
  h5::write_attr(c, root, "generations_planned", int64_t{s.config.generations});
  h5::write_attr(c, root, "generations_done", int64_t{s.generations_done});
  h5::write_attr(c, root, "finished", int64_t{s.finished() ? 1 : 0});
  h5::write_attr(c, root, "content_digest", content_digest(s).hex());
  h5::write_attr(c, root, "checkpoint_digest", layout::checkpoint_digest(s).hex());
  for_each_field(p, [&](const char* name, const auto& v) { h5::write_attr(c, root, name, v); });
}

void write_generations(const Ctx& c, hid_t root, const RunState& s) {
  Handle g = h5::create_group(c, root, "generations");
  const hsize_t G = s.history.size();
  const hsize_t P = G ? s.history[0].id.size() : 0;
  // The population's fields: (G, P), a row a generation.
  const auto matrix = [&](const char* name, auto member) {
    std::decay_t<decltype(s.history[0].*member)> all;
    for (const GenerationRecord& r : s.history) {
      if ((r.*member).size() != P)
        c.fail("/generations", "internal error: population size changed");
      all.insert(all.end(), (r.*member).begin(), (r.*member).end());
    }
    h5::write(c, g.id(), name, all, {G, P});
  };
  matrix("id", &GenerationRecord::id);
  matrix("parent_id", &GenerationRecord::parent_id);
  matrix("age", &GenerationRecord::age);
  matrix("fitness", &GenerationRecord::fitness);
  matrix("status", &GenerationRecord::status);
  const std::vector<GenerationRecord>& h = s.history;
  h5::write_column(c, g.id(), "champion_id", h, &GenerationRecord::champion_id);
  h5::write_column(c, g.id(), "best_fitness", h, &GenerationRecord::best_fitness);
  h5::write_column(c, g.id(), "simulated", h, &GenerationRecord::simulated);
  h5::write_column(c, g.id(), "cache_hits", h, &GenerationRecord::cache_hits);
  h5::write_column(c, g.id(), "wall_seconds", h, &GenerationRecord::wall_seconds);
  h5::write_units(c, g.id(), "fitness", fitness_unit(s));
  h5::write_units(c, g.id(), "best_fitness", fitness_unit(s));
  h5::write_units(c, g.id(), "wall_seconds", "s");
  if (s.config.algorithm == Algorithm::kMapElites) {  // the archive over evaluations
    const double cells = static_cast<double>(s.config.map_elites.cells());
    std::vector<int64_t> evaluations(h.size(), 0);
    for (const BirthRecord& b : s.births) ++evaluations[static_cast<size_t>(b.generation)];
    for (size_t k = 1; k < evaluations.size(); ++k) evaluations[k] += evaluations[k - 1];
    h5::write(c, g.id(), "evaluations", evaluations);
    h5::write_column(c, g.id(), "qd_score", h, &GenerationRecord::qd_score);
    h5::write_column(c, g.id(), "filled", h, &GenerationRecord::filled);
    h5::write_column<double>(c, g.id(), "coverage", h,
                             [&](const GenerationRecord& r) { return r.filled / cells; });
    h5::write_units(c, g.id(), "qd_score", fitness_unit(s));
  }
}

void write_individuals(const Ctx& c, hid_t root, const RunState& s) {
  Handle g = h5::create_group(c, root, "individuals");
  const std::vector<BirthRecord>& b = s.births;
  h5::write_column(c, g.id(), "id", b, &BirthRecord::id);
  layout::for_each_birth_column(
      [&](const char* name, auto member) { h5::write_column(c, g.id(), name, b, member); });
  h5::write_units(c, g.id(), "fitness", fitness_unit(s));
  h5::write_column(c, g.id(), "sank", b, &BirthRecord::sank);
  h5::write_column(c, g.id(), "vertical", b, &BirthRecord::vertical);
  // Failures are rare: stored sparsely, by id.
  std::vector<uint64_t> failure_id;
  std::vector<std::string> failure;
  for (const BirthRecord& r : b)
    if (!r.failure.empty()) {
      failure_id.push_back(r.id);
      failure.push_back(r.failure);
    }
  h5::write(c, g.id(), "failure_id", failure_id);
  h5::write_strings(c, g.id(), "failure_reason", failure);
  if (s.config.algorithm == Algorithm::kMapElites) {  // (N, D), NaN where not measured
    const hsize_t D = s.config.map_elites.axes.size();
    std::vector<double> d;
    for (const BirthRecord& r : b) {
      if (r.descriptors.size() != D) c.fail("/individuals/descriptors", "internal error: count");
      d.insert(d.end(), r.descriptors.begin(), r.descriptors.end());
    }
    h5::write(c, g.id(), "descriptors", d, {static_cast<hsize_t>(b.size()), D});
  }
}

void write_champions(const Ctx& c, hid_t root, const RunState& s) {
  Handle all = h5::create_group(c, root, "champions");
  for (size_t k = 0; k < s.champions.size(); ++k) {
    const ChampionRecord& ch = s.champions[k];
    Handle g = h5::create_group(c, all.id(), layout::champion_name(k));
    h5::write_attr(c, g.id(), "generation", int64_t{ch.generation});
    h5::write_attr_u64(c, g.id(), "id", ch.id);
    h5::write_attr(c, g.id(), "parent_id", ch.parent_id);
    h5::write_attr(c, g.id(), "age", int64_t{ch.age});
    h5::write_attr(c, g.id(), "fitness", ch.fitness);
    h5::write_attr(c, g.id(), "status", std::string(to_string(static_cast<EvalStatus>(ch.status))));
    Handle genome = h5::create_group(c, g.id(), "genome");
    for (int n = 0; n < kNetworkCount; ++n) {
      Handle net = h5::create_group(c, genome.id(), layout::kNetworkNames[n]);
      write_network(c, net.id(), ch.genome.nets[n]);
    }
    if (!ch.genome.controller.empty())
      h5::write(c, genome.id(), "controller", ch.genome.controller);
    Handle ph = h5::create_group(c, g.id(), "phenotype");
    write_phenotype(c, ph.id(), ch.phenotype);
    h5::write(c, g.id(), "final_stiffness", ch.final_stiffness, lattice_dims(ch.phenotype));
    h5::write_units(c, g.id(), "final_stiffness", "Pa");
  }
  if (!s.champions.empty()) {
    const std::string target = "/champions/" + layout::champion_name(s.champions.size() - 1);
    if (H5Lcreate_soft(target.c_str(), root, "champion", H5P_DEFAULT, H5P_DEFAULT) < 0)
      c.fail("/champion", "cannot create link");
  }
}

// Genomes, stacked per network: individual i owns nodes [node_offset[i], node_offset[i+1]) and
// links [link_offset[i], link_offset[i+1]); the controllers' weights, (P, count), when the run
// evolves a controller.
void write_genomes(const Ctx& c, hid_t parent, const std::string& obj,
                   const std::vector<Individual>& members, hsize_t count) {
  Handle genomes = h5::create_group(c, parent, "genome");
  for (int n = 0; n < kNetworkCount; ++n) {
    std::vector<int64_t> node_off = {0}, link_off = {0};
    std::vector<uint8_t> act;
    std::vector<int32_t> src, dst;
    std::vector<double> w;
    for (const Individual& ind : members) {
      const Cppn& net = ind.genome.nets[n];
      for (Activation a : net.nodes) act.push_back(static_cast<uint8_t>(a));
      for (const CppnLink& l : net.links) {
        src.push_back(l.source);
        dst.push_back(l.target);
        w.push_back(l.weight);
      }
      node_off.push_back(static_cast<int64_t>(act.size()));
      link_off.push_back(static_cast<int64_t>(w.size()));
    }
    Handle g = h5::create_group(c, genomes.id(), layout::kNetworkNames[n]);
    h5::write(c, g.id(), "node_offset", node_off);
    h5::write(c, g.id(), "activation", act);
    h5::write(c, g.id(), "link_offset", link_off);
    h5::write(c, g.id(), "source", src);
    h5::write(c, g.id(), "target", dst);
    h5::write(c, g.id(), "weight", w);
  }
  if (count > 0) {
    std::vector<double> w;
    for (const Individual& ind : members)
      w.insert(w.end(), ind.genome.controller.begin(), ind.genome.controller.end());
    if (w.size() != members.size() * count)
      c.fail(obj + "/genome/controller", "internal error: weight count");
    h5::write(c, genomes.id(), "controller", w, {static_cast<hsize_t>(members.size()), count});
  }
}

// Algorithm map-elites: the archive, one row per filled cell in ascending cell order (also
// what a resumed run continues from).
void write_archive(const Ctx& c, hid_t root, const RunState& s) {
  const MapElitesSettings& me = s.config.map_elites;
  Handle g = h5::create_group(c, root, "archive");
  std::string names;
  for (const DescriptorAxis& a : me.axes) {
    if (!names.empty()) names += ",";
    names += to_string(a.what);
  }
  h5::write_attr(c, g.id(), "descriptors", names);
  h5::write_attr(c, g.id(), "cells", int64_t{me.cells()});
  h5::write_attr(c, g.id(), "qd_offset", me.qd_offset);
  const std::vector<Individual>& e = s.archive;
  h5::write_column(c, g.id(), "cell", e, &Individual::cell);
  h5::write_column(c, g.id(), "id", e, &Individual::id);
  h5::write_column(c, g.id(), "parent_id", e, &Individual::parent_id);
  h5::write_column(c, g.id(), "born", e, &Individual::born);
  h5::write_column(c, g.id(), "fitness", e, &Individual::fitness);
  h5::write_units(c, g.id(), "fitness", fitness_unit(s));
  const hsize_t D = me.axes.size();
  std::vector<double> d;
  std::vector<int32_t> bins;
  for (const Individual& ind : e) {
    d.insert(d.end(), ind.descriptors.begin(), ind.descriptors.end());
    for (int b : bins_of(me, ind.cell)) bins.push_back(b);
  }
  h5::write(c, g.id(), "descriptors", d, {static_cast<hsize_t>(e.size()), D});
  h5::write(c, g.id(), "bins", bins, {static_cast<hsize_t>(e.size()), D});
  write_genomes(c, g.id(), "/archive", e, static_cast<hsize_t>(s.config.controller_genes.count));
}

void write_checkpoint(const Ctx& c, hid_t root, const RunState& s) {
  Handle ck = h5::create_group(c, root, "checkpoint");
  h5::write_attr_u64(c, ck.id(), "next_id", s.next_id);
  Handle pop = h5::create_group(c, ck.id(), "population");
  const std::vector<Individual>& p = s.population;
  layout::for_each_member_column(
      [&](const char* name, auto member) { h5::write_column(c, pop.id(), name, p, member); });
  h5::write_units(c, pop.id(), "fitness", fitness_unit(s));
  h5::write_column<uint8_t>(c, pop.id(), "status", p, [](const Individual& i) { return i.status; });
  write_genomes(c, pop.id(), "/checkpoint/population", p,
                static_cast<hsize_t>(s.config.controller_genes.count));
  if (s.config.algorithm == Algorithm::kCmaEs) {  // the search distribution (cma.hpp)
    const hsize_t n = s.cma.mean.size();
    Handle g = h5::create_group(c, ck.id(), "cma");
    h5::write_attr(c, g.id(), "sigma", s.cma.sigma);
    h5::write_attr(c, g.id(), "updates", int64_t{s.cma.updates});
    h5::write(c, g.id(), "mean", s.cma.mean);
    h5::write(c, g.id(), "p_sigma", s.cma.p_sigma);
    h5::write(c, g.id(), "p_c", s.cma.p_c);
    if (s.cma.separable)
      h5::write(c, g.id(), "cov", s.cma.cov);
    else
      h5::write(c, g.id(), "cov", s.cma.cov, {n, n});
  }
  Handle cache = h5::create_group(c, ck.id(), "cache");
  std::vector<uint64_t> hi, lo, failure_row;
  std::vector<double> fit;
  std::vector<uint8_t> st, sank, vertical;
  std::vector<std::string> failure;
  for (const auto& [key, e] : s.cache) {
    sank.push_back(e.sank ? 1 : 0);
    vertical.push_back(e.vertical ? 1 : 0);
    if (!e.failure.empty()) {
      failure_row.push_back(hi.size());
      failure.push_back(e.failure);
    }
    hi.push_back(key.hi);
    lo.push_back(key.lo);
    fit.push_back(e.fitness);
    st.push_back(static_cast<uint8_t>(e.status));
  }
  h5::write(c, cache.id(), "hash_hi", hi);
  h5::write(c, cache.id(), "hash_lo", lo);
  h5::write(c, cache.id(), "fitness", fit);
  h5::write_units(c, cache.id(), "fitness", fitness_unit(s));
  h5::write(c, cache.id(), "status", st);
  h5::write(c, cache.id(), "sank", sank);
  h5::write(c, cache.id(), "vertical", vertical);
  h5::write(c, cache.id(), "failure_row", failure_row);
  h5::write_strings(c, cache.id(), "failure_reason", failure);
  if (s.config.algorithm == Algorithm::kMapElites) {  // what each life gave the descriptors
    std::vector<uint8_t> measured;
    std::vector<double> m;
    for (const auto& [key, e] : s.cache) {
      measured.push_back(e.measures.measured ? 1 : 0);
      m.insert(m.end(), {e.measures.floor_contact, e.measures.com_height, e.measures.development});
    }
    h5::write(c, cache.id(), "measured", measured);
    h5::write(c, cache.id(), "measures", m, {static_cast<hsize_t>(measured.size()), 3});
  }
}

}  // namespace

void write_results(const std::string& path, const RunState& s, const Provenance& prov) {
  const Ctx c{path, 0};
  // Built in memory (h5::MemoryFile: a full disk never reaches HDF5), sealed, then written
  // to a temporary file and renamed over path, so the previous file stays intact until the
  // new one is complete on disk.
  std::string bytes;
  {
    h5::MemoryFile f(c, seal::kUserBlockBytes);
    {
      Handle root = h5::open_group(c, f.id(), "/");
      write_root_attributes(c, root.id(), s, prov);
      write_generations(c, root.id(), s);
      write_individuals(c, root.id(), s);
      write_champions(c, root.id(), s);
      write_checkpoint(c, root.id(), s);
      if (s.config.algorithm == Algorithm::kMapElites) write_archive(c, root.id(), s);
    }
    bytes = f.image();
  }
  seal::seal_image(bytes, path);
  try {
    write_file_atomic(path, bytes);
  } catch (const InputError& e) {  // a results-file error for the caller (and MPI's rank 0)
    throw ResultsError(e.what());
  }
}

}  // namespace plastivox::evo
