// Reading and checking the results file. Every dataset's class and shape is checked before
// it is read, every cross-reference after, and both digests at the end: a file that
// passes is exactly what a writer produced.
#include <nlohmann/json.hpp>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/cma_body.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/file_seal.hpp"
#include "plastivox/io/h5_util.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/limits.hpp"
#include "results_layout.hpp"

namespace plastivox::evo {
namespace {

using h5::Ctx;
using h5::Handle;

Cppn make_network(const Ctx& c, const std::string& obj, const std::vector<uint8_t>& act,
                  const std::vector<int32_t>& src, const std::vector<int32_t>& dst,
                  const std::vector<double>& w) {
  Cppn net;
  for (uint8_t a : act) {
    if (a > static_cast<uint8_t>(Activation::kIdentity)) c.fail(obj, "unknown activation code");
    net.nodes.push_back(static_cast<Activation>(a));
  }
  for (size_t k = 0; k < src.size(); ++k) net.links.push_back({src[k], dst[k], w[k]});
  try {
    validate(net);
  } catch (const std::invalid_argument& e) {
    c.fail(obj, std::string("invalid network: ") + e.what());
  }
  return net;
}

Cppn read_network(const Ctx& c, hid_t group, const std::string& obj) {
  const auto act = h5::read<uint8_t>(c, group, "activation", h5::kAnyExtent);
  std::vector<hsize_t> dims = {h5::kAnyExtent};
  const auto src = h5::read<int32_t>(c, group, "source", dims);
  const auto dst = h5::read<int32_t>(c, group, "target", dims[0]);
  const auto w = h5::read<double>(c, group, "weight", dims[0]);
  return make_network(c, obj, act, src, dst, w);
}

RobotDef read_phenotype(const Ctx& c, hid_t group, const EvolveConfig& cfg) {
  RobotDef r = make_empty_robot(cfg.nx, cfg.ny, cfg.nz, cfg.voxel_size, limits_from_environment());
  std::vector<hsize_t> dims = {hsize_t(cfg.nz), hsize_t(cfg.ny), hsize_t(cfg.nx)};
  r.present = h5::read<uint8_t>(c, group, "present", dims);
  r.stiffness = h5::read<double>(c, group, "stiffness", dims);
  r.dev_rate = h5::read<double>(c, group, "dev_rate", dims);
  r.phase = h5::read<double>(c, group, "phase", dims);
  return r;
}

EvalStatus status_code(const Ctx& c, const std::string& obj, uint8_t v) {
  if (v > static_cast<uint8_t>(EvalStatus::kUnstable)) c.fail(obj, "unknown status code");
  return static_cast<EvalStatus>(v);
}

void read_generations(const Ctx& c, hid_t root, RunState& s) {
  Handle g = h5::open_group(c, root, "generations");
  const hsize_t G = static_cast<hsize_t>(s.generations_done + 1);
  const hsize_t P = static_cast<hsize_t>(s.config.population);
  std::vector<hsize_t> d2 = {G, P};
  const auto id = h5::read<uint64_t>(c, g.id(), "id", d2);
  const auto parent = h5::read<int64_t>(c, g.id(), "parent_id", d2);
  const auto age = h5::read<int32_t>(c, g.id(), "age", d2);
  const auto fitness = h5::read<double>(c, g.id(), "fitness", d2);
  const auto status = h5::read<uint8_t>(c, g.id(), "status", d2);
  const auto champion = h5::read<uint64_t>(c, g.id(), "champion_id", G);
  const auto best = h5::read<double>(c, g.id(), "best_fitness", G);
  const auto simulated = h5::read<int32_t>(c, g.id(), "simulated", G);
  const auto hits = h5::read<int32_t>(c, g.id(), "cache_hits", G);
  const auto wall = h5::read<double>(c, g.id(), "wall_seconds", G);
  for (hsize_t k = 0; k < G; ++k) {
    GenerationRecord r;
    const auto row = [&](const auto& v) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      return std::vector<T>(v.begin() + k * P, v.begin() + (k + 1) * P);
    };
    r.id = row(id);
    r.parent_id = row(parent);
    r.age = row(age);
    r.fitness = row(fitness);
    r.status = row(status);
    for (uint8_t x : r.status) status_code(c, "/generations/status", x);
    r.champion_id = champion[k];
    r.best_fitness = best[k];
    r.simulated = simulated[k];
    r.cache_hits = hits[k];
    r.wall_seconds = wall[k];
    s.history.push_back(std::move(r));
  }
  if (s.config.algorithm == Algorithm::kMapElites) {  // the archive over evaluations
    const auto qd = h5::read<double>(c, g.id(), "qd_score", G);
    const auto filled = h5::read<int64_t>(c, g.id(), "filled", G);
    for (hsize_t k = 0; k < G; ++k) {
      s.history[k].qd_score = qd[k];
      s.history[k].filled = filled[k];
    }
  }
}

void read_individuals(const Ctx& c, hid_t root, RunState& s) {
  Handle g = h5::open_group(c, root, "individuals");
  const hsize_t N = s.next_id;
  // The ids first: reading them checks the row count before N rows are made.
  const auto id = h5::read<uint64_t>(c, g.id(), "id", N);
  std::vector<BirthRecord>& b = s.births;
  b.resize(N);
  for (hsize_t i = 0; i < N; ++i) {
    if (id[i] != i) c.fail("/individuals/id", "ids must be 0, 1, 2, ... in order");
    b[i].id = i;
  }
  layout::for_each_birth_column(
      [&](const char* name, auto member) { h5::read_column(c, g.id(), name, b, member); });
  // Health flag added after format version 1 was fixed: absent in older files (all 0).
  if (h5::has_link(g.id(), "sank")) h5::read_column(c, g.id(), "sank", b, &BirthRecord::sank);
  // The vertical flag, added on 2026-12-06: absent in older files, whose lives read as not
  // flagged (their evolver did not look; docs/results-format.md says what that assumes).
  if (h5::has_link(g.id(), "vertical"))
    h5::read_column(c, g.id(), "vertical", b, &BirthRecord::vertical);
  for (BirthRecord& r : b) {
    status_code(c, "/individuals/status", r.status);
    r.sank = r.sank ? 1 : 0;
    r.vertical = r.vertical ? 1 : 0;
  }
  std::vector<hsize_t> fd = {h5::kAnyExtent};
  const auto failure_id = h5::read<uint64_t>(c, g.id(), "failure_id", fd);
  const auto failure = h5::read_strings(c, g.id(), "failure_reason", fd[0]);
  for (size_t k = 0; k < failure_id.size(); ++k) {
    if (failure_id[k] >= N) c.fail("/individuals/failure_id", "refers to an unknown individual");
    b[failure_id[k]].failure = failure[k];
  }
  if (s.config.algorithm == Algorithm::kMapElites) {  // (N, D)
    const hsize_t D = s.config.map_elites.axes.size();
    std::vector<hsize_t> dd = {N, D};
    const auto d = h5::read<double>(c, g.id(), "descriptors", dd);
    for (hsize_t i = 0; i < N; ++i)
      b[i].descriptors.assign(d.begin() + i * D, d.begin() + (i + 1) * D);
  }
}

void read_champions(const Ctx& c, hid_t root, RunState& s) {
  Handle all = h5::open_group(c, root, "champions");
  H5G_info_t info;
  if (H5Gget_info(all.id(), &info) < 0) c.fail("/champions", "cannot list");
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    const std::string name = layout::champion_name(k);
    const std::string obj = "/champions/" + name;
    Handle g = h5::open_group(c, all.id(), name);
    ChampionRecord ch;
    ch.generation = static_cast<int32_t>(h5::read_attr_int(c, g.id(), obj, "generation"));
    ch.id = h5::read_attr_u64(c, g.id(), obj, "id");
    ch.parent_id = h5::read_attr_int(c, g.id(), obj, "parent_id");
    ch.age = static_cast<int32_t>(h5::read_attr_int(c, g.id(), obj, "age"));
    ch.fitness = h5::read_attr_double(c, g.id(), obj, "fitness");
    const std::string st = h5::read_attr_string(c, g.id(), obj, "status");
    bool known = false;
    for (uint8_t code = 0; code <= 2; ++code)
      if (st == to_string(static_cast<EvalStatus>(code))) ch.status = code, known = true;
    if (!known) c.fail(obj + "@status", "unknown status '" + st + "'");
    Handle genome = h5::open_group(c, g.id(), "genome");
    for (int n = 0; n < kNetworkCount; ++n) {
      Handle net = h5::open_group(c, genome.id(), layout::kNetworkNames[n]);
      ch.genome.nets[n] = read_network(c, net.id(), obj + "/genome/" + layout::kNetworkNames[n]);
    }
    const hsize_t weights = static_cast<hsize_t>(s.config.controller_genes.count);
    if (weights > 0) ch.genome.controller = h5::read<double>(c, genome.id(), "controller", weights);
    Handle ph = h5::open_group(c, g.id(), "phenotype");
    ch.phenotype = read_phenotype(c, ph.id(), s.config);
    // Its controller: the run's, with the genome's weights (as the expresser made it).
    ch.phenotype.controller = s.config.controller;
    ch.phenotype.controller.weights = ch.genome.controller;
    if (s.config.algorithm == Algorithm::kCmaEs) {  // the fixed body with the genome applied
      const RobotDef made = express_vector(s.config, ch.genome.controller).robot;
      if (made.present != ch.phenotype.present || made.stiffness != ch.phenotype.stiffness ||
          made.dev_rate != ch.phenotype.dev_rate || made.phase != ch.phenotype.phase)
        c.fail(obj + "/phenotype", "is not the run's body with the champion's genome");
      ch.phenotype = made;
    }
    std::vector<hsize_t> dims = {hsize_t(s.config.nz), hsize_t(s.config.ny), hsize_t(s.config.nx)};
    ch.final_stiffness = h5::read<double>(c, g.id(), "final_stiffness", dims);
    s.champions.push_back(std::move(ch));
  }
}

// The genomes write_genomes stacked (results_write.cpp), into members (already sized).
void read_genomes(const Ctx& c, hid_t parent, const std::string& where,
                  std::vector<Individual>& members, hsize_t count) {
  const hsize_t P = members.size();
  Handle genomes = h5::open_group(c, parent, "genome");
  for (int n = 0; n < kNetworkCount; ++n) {
    const std::string obj = where + "/genome/" + layout::kNetworkNames[n];
    Handle g = h5::open_group(c, genomes.id(), layout::kNetworkNames[n]);
    const auto node_off = h5::read<int64_t>(c, g.id(), "node_offset", P + 1);
    const auto link_off = h5::read<int64_t>(c, g.id(), "link_offset", P + 1);
    const auto act = h5::read<uint8_t>(c, g.id(), "activation", h5::kAnyExtent);
    std::vector<hsize_t> ld = {h5::kAnyExtent};
    const auto src = h5::read<int32_t>(c, g.id(), "source", ld);
    const auto dst = h5::read<int32_t>(c, g.id(), "target", ld[0]);
    const auto w = h5::read<double>(c, g.id(), "weight", ld[0]);
    for (hsize_t i = 0; i < P; ++i) {
      const int64_t n0 = node_off[i], n1 = node_off[i + 1], l0 = link_off[i], l1 = link_off[i + 1];
      if (n0 < 0 || n1 < n0 || n1 > static_cast<int64_t>(act.size()) || l0 < 0 || l1 < l0 ||
          l1 > static_cast<int64_t>(w.size()))
        c.fail(obj, "offsets out of range");
      members[i].genome.nets[n] = make_network(
          c, obj, {act.begin() + n0, act.begin() + n1}, {src.begin() + l0, src.begin() + l1},
          {dst.begin() + l0, dst.begin() + l1}, {w.begin() + l0, w.begin() + l1});
    }
  }
  if (count > 0) {
    std::vector<hsize_t> dims = {P, count};
    const auto w = h5::read<double>(c, genomes.id(), "controller", dims);
    for (hsize_t i = 0; i < P; ++i)
      members[i].genome.controller.assign(w.begin() + i * count, w.begin() + (i + 1) * count);
  }
}

// Algorithm map-elites: the archive (write_archive), each elite in the cell its descriptors
// give, cells ascending.
void read_archive(const Ctx& c, hid_t root, RunState& s) {
  const MapElitesSettings& me = s.config.map_elites;
  Handle g = h5::open_group(c, root, "archive");
  std::vector<hsize_t> ed = {h5::kAnyExtent};
  const auto cell = h5::read<int64_t>(c, g.id(), "cell", ed);
  const hsize_t E = ed[0];
  if (E > static_cast<hsize_t>(me.cells())) c.fail("/archive/cell", "more elites than cells");
  std::vector<Individual>& e = s.archive;
  e.resize(E);
  h5::read_column(c, g.id(), "id", e, &Individual::id);
  h5::read_column(c, g.id(), "parent_id", e, &Individual::parent_id);
  h5::read_column(c, g.id(), "born", e, &Individual::born);
  h5::read_column(c, g.id(), "fitness", e, &Individual::fitness);
  const hsize_t D = me.axes.size();
  std::vector<hsize_t> dd = {E, D};
  const auto d = h5::read<double>(c, g.id(), "descriptors", dd);
  for (hsize_t i = 0; i < E; ++i) {
    e[i].cell = cell[i];
    e[i].status = EvalStatus::kOk;
    e[i].descriptors.assign(d.begin() + i * D, d.begin() + (i + 1) * D);
    if (cell_of(me, e[i].descriptors) != cell[i] || (i > 0 && cell[i] <= cell[i - 1]) ||
        e[i].id >= s.next_id)
      c.fail("/archive", "an elite is not in the cell its descriptors give, or out of order");
  }
  read_genomes(c, g.id(), "/archive", e, static_cast<hsize_t>(s.config.controller_genes.count));
}

void read_checkpoint(const Ctx& c, hid_t root, RunState& s) {
  Handle ck = h5::open_group(c, root, "checkpoint");
  Handle pop = h5::open_group(c, ck.id(), "population");
  const hsize_t P = s.history.empty() ? 0 : s.history.back().id.size();
  std::vector<Individual>& members = s.population;
  members.resize(P);
  layout::for_each_member_column(
      [&](const char* name, auto member) { h5::read_column(c, pop.id(), name, members, member); });
  const auto status = h5::read<uint8_t>(c, pop.id(), "status", P);
  for (hsize_t i = 0; i < P; ++i) {
    Individual& ind = members[i];
    ind.status = status_code(c, "/checkpoint/population/status", status[i]);
    if (ind.id != s.history.back().id[i] || ind.age != s.history.back().age[i])
      c.fail("/checkpoint/population", "does not match the last generation's population");
  }
  read_genomes(c, pop.id(), "/checkpoint/population", members,
               static_cast<hsize_t>(s.config.controller_genes.count));
  if (s.config.algorithm == Algorithm::kCmaEs) {  // the search distribution (cma.hpp)
    const hsize_t n = static_cast<hsize_t>(s.config.controller_genes.count);
    Handle g = h5::open_group(c, ck.id(), "cma");
    CmaState& m = s.cma;
    m.separable = s.config.cma.separable;
    m.sigma = h5::read_attr_double(c, g.id(), "/checkpoint/cma", "sigma");
    m.updates = static_cast<int>(h5::read_attr_int(c, g.id(), "/checkpoint/cma", "updates"));
    m.mean = h5::read<double>(c, g.id(), "mean", n);
    m.p_sigma = h5::read<double>(c, g.id(), "p_sigma", n);
    m.p_c = h5::read<double>(c, g.id(), "p_c", n);
    std::vector<hsize_t> dims = {n, n};
    m.cov = m.separable ? h5::read<double>(c, g.id(), "cov", n)
                        : h5::read<double>(c, g.id(), "cov", dims);
  }
  Handle cache = h5::open_group(c, ck.id(), "cache");
  std::vector<hsize_t> cd = {h5::kAnyExtent};
  const auto hi = h5::read<uint64_t>(c, cache.id(), "hash_hi", cd);
  const auto lo = h5::read<uint64_t>(c, cache.id(), "hash_lo", cd[0]);
  const auto fit = h5::read<double>(c, cache.id(), "fitness", cd[0]);
  const auto st = h5::read<uint8_t>(c, cache.id(), "status", cd[0]);
  const auto sank = h5::has_link(cache.id(), "sank")
                        ? h5::read<uint8_t>(c, cache.id(), "sank", cd[0])
                        : std::vector<uint8_t>(hi.size(), 0);
  const auto vertical = h5::has_link(cache.id(), "vertical")  // absent in older files: 0
                            ? h5::read<uint8_t>(c, cache.id(), "vertical", cd[0])
                            : std::vector<uint8_t>(hi.size(), 0);
  std::vector<hsize_t> fd = {h5::kAnyExtent};
  const auto failure_row = h5::read<uint64_t>(c, cache.id(), "failure_row", fd);
  const auto failure = h5::read_strings(c, cache.id(), "failure_reason", fd[0]);
  std::vector<std::string> reasons(hi.size());
  for (size_t k = 0; k < failure_row.size(); ++k) {
    if (failure_row[k] >= hi.size()) c.fail("/checkpoint/cache/failure_row", "out of range");
    reasons[failure_row[k]] = failure[k];
  }
  std::vector<DescriptorMeasures> measures(hi.size());
  if (s.config.algorithm == Algorithm::kMapElites) {  // what each life gave the descriptors
    const auto measured = h5::read<uint8_t>(c, cache.id(), "measured", cd[0]);
    std::vector<hsize_t> md = {cd[0], 3};
    const auto m = h5::read<double>(c, cache.id(), "measures", md);
    for (size_t k = 0; k < hi.size(); ++k)
      measures[k] = {measured[k] != 0, m[3 * k], m[3 * k + 1], m[3 * k + 2]};
  }
  for (size_t k = 0; k < hi.size(); ++k)
    s.cache[Hash128{hi[k], lo[k]}] =
        CacheEntry{fit[k],      status_code(c, "/checkpoint/cache/status", st[k]),
                   reasons[k],  sank[k] != 0,
                   measures[k], vertical[k] != 0};
}

}  // namespace

ResultsFile read_results(const std::string& path) {
  const Ctx c = h5::read_context(path);
  seal::check_seal(path);  // before HDF5 parses anything
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw ResultsError(path +
                       ": not an HDF5 file (wrong format, or the file is corrupt or truncated)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Handle::Kind::kFile);
  if (f.id() < 0)
    throw ResultsError(path + ": cannot open as HDF5 (the file is corrupt or truncated)");
  Handle root = h5::open_group(c, f.id(), "/");
  const hid_t r = root.id();
  if (!h5::has_attr(r, "format") || h5::read_attr_string(c, r, "/", "format") != layout::kFormat)
    throw ResultsError(path + ": not a plastivox evolution results file (no format attribute \"" +
                       std::string(layout::kFormat) + "\" on /)");
  const int64_t version = h5::read_attr_int(c, r, "/", "format_version");
  if (version != kResultsFormatVersion)
    throw ResultsError(path + ": results format version " + std::to_string(version) +
                       " is not supported (this build reads " +
                       std::to_string(kResultsFormatVersion) + ")");

  ResultsFile out;
  RunState& s = out.state;
  try {
    s.config = parse_config(h5::read_attr_string(c, r, "/", "config"), path + ": /@config");
  } catch (const InputError& e) {
    throw ResultsError(e.what());
  }
  // The rule for sunk lives the run selected under, as its resolved physics spells it.
  if (h5::has_attr(r, "resolved_physics")) {
    const std::string text = h5::read_attr_string(c, r, "/", "resolved_physics");
    nlohmann::json p;
    try {  // bounded like every input (depth, NUL)
      p = parse_json_input(text, path, "/@resolved_physics");
    } catch (const InputError& e) {
      throw ResultsError(e.what());
    }
    if (!p.is_object()) c.fail("/@resolved_physics", "is not a JSON object");
    s.config.physics.sinking_invalid = sinking_invalid_in(text);
  }
  s.generations_done = static_cast<int>(h5::read_attr_int(c, r, "/", "generations_done"));
  if (s.generations_done < 0 || s.generations_done > s.config.generations)
    c.fail("/@generations_done", "out of range for the configured generations");
  Handle ck = h5::open_group(c, r, "checkpoint");
  s.next_id = h5::read_attr_u64(c, ck.id(), "/checkpoint", "next_id");
  if (s.next_id > c.file_size) c.fail("/checkpoint@next_id", "implausible");
  read_generations(c, r, s);
  read_individuals(c, r, s);
  read_champions(c, r, s);
  read_checkpoint(c, r, s);
  if (s.config.algorithm == Algorithm::kMapElites) read_archive(c, r, s);

  for_each_field(out.provenance, [&](const char* name, auto& v) {
    // Files written before 2026-12-05 do not say what scored them: the engine did.
    if (std::string_view(name) == "fitness_function" && !h5::has_attr(r, name)) return;
    h5::read_attr(c, r, "/", name, v);
  });

  out.content_digest = h5::read_attr_string(c, r, "/", "content_digest");
  if (content_digest(s).hex() != out.content_digest)
    c.fail("/@content_digest", "does not match the content (the file was modified or is corrupt)");
  if (layout::checkpoint_digest(s).hex() != h5::read_attr_string(c, r, "/", "checkpoint_digest"))
    c.fail("/@checkpoint_digest",
           "does not match the checkpoint (the file was modified or is corrupt)");
  ck.reset();
  root.reset();
  if (f.close() < 0) throw ResultsError(path + ": error while closing the file");
  return out;
}

}  // namespace plastivox::evo
