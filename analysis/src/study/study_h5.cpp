// analysis.h5: the study's results in HDF5 (layout in docs/analysis.md, "analysis.h5"), with the
// same content as stats.json plus provenance, per-pair placements and timings. Undefined values
// are NaN here (HDF5 has no null). Uses the evolver's checked HDF5 wrappers (h5_util.hpp), so
// every failure is one line naming the file and the object.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/h5_util.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {
namespace {

using h5::Ctx;
using h5::Handle;

constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

double value(const std::optional<double>& x) {
  return x ? *x : kUndefined;
}

void write_inputs(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle g = h5::create_group(c, root, "inputs");
  std::vector<std::string> file, digest, treatment, physics;
  std::vector<uint64_t> seed;
  std::vector<int32_t> generation, done, body_plan_start;
  for (const StudyInput& in : r.inputs) {
    file.push_back(in.file);
    digest.push_back(in.content_digest);
    treatment.push_back(to_string(in.treatment));
    physics.push_back(in.physics_json);
    seed.push_back(in.seed);
    generation.push_back(in.generation);
    done.push_back(in.generations_done);
    body_plan_start.push_back(in.body_plan_start ? 1 : 0);
  }
  h5::write_strings(c, g.id(), "file", file);
  h5::write_strings(c, g.id(), "content_digest", digest);
  h5::write_strings(c, g.id(), "treatment", treatment);
  h5::write_strings(c, g.id(), "physics_json", physics);
  h5::write(c, g.id(), "seed", seed);
  h5::write(c, g.id(), "generation", generation);
  h5::write(c, g.id(), "generations_done", done);
  h5::write(c, g.id(), "body_plan_start", body_plan_start);
}

void write_champions(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle g = h5::create_group(c, root, "champions");
  const size_t n = r.champions.size(), draws = static_cast<size_t>(r.options.robustness_draws);
  std::vector<std::string> label, treatment, evaluation, status, detail, health, plan, digest,
      excluded;
  std::vector<uint64_t> seed, id, rseed;
  std::vector<int32_t> generation, voxels, input, valid;
  std::vector<double> fitness, f_train, r_mean, m_body, v_body, v_gain, confidence, depth, vertical;
  std::vector<double> r_draw(n * draws, kUndefined), f_test(n * draws, kUndefined);
  for (size_t i = 0; i < n; ++i) {
    const ChampionAnalysis& ch = r.champions[i];
    label.push_back(ch.label);
    treatment.push_back(to_string(ch.treatment));
    evaluation.push_back(ch.evaluation);
    status.push_back(ch.status);
    detail.push_back(ch.status_detail);
    health.push_back(ch.health);
    excluded.push_back(ch.artifact);
    depth.push_back(ch.floor_depth);
    vertical.push_back(ch.vertical_share);
    plan.push_back(to_string(ch.body_plan.plan));
    digest.push_back(ch.phenotype_digest);
    seed.push_back(ch.run_seed);
    id.push_back(ch.id);
    rseed.push_back(ch.robustness_seed);
    generation.push_back(ch.generation);
    voxels.push_back(ch.voxels);
    input.push_back(ch.input);
    valid.push_back(ch.robustness.valid_draws);
    fitness.push_back(ch.evaluation == "ok" ? ch.fitness : kUndefined);
    f_train.push_back(ch.robustness.train_valid ? ch.robustness.f_train : kUndefined);
    r_mean.push_back(value(ch.r_mean));
    m_body.push_back(value(ch.m_body));
    v_body.push_back(value(ch.v_body));
    v_gain.push_back(value(ch.v_gain));
    confidence.push_back(ch.body_plan.confidence);
    for (size_t k = 0; k < ch.robustness.draws.size() && k < draws; ++k) {
      const RobustnessDraw& d = ch.robustness.draws[k];
      if (!d.valid) continue;
      r_draw[i * draws + k] = d.r;
      f_test[i * draws + k] = d.f_test;
    }
  }
  using Strings = std::pair<const char*, const std::vector<std::string>*>;
  for (const auto& [name, v] : std::initializer_list<Strings>{{"label", &label},
                                                              {"treatment", &treatment},
                                                              {"evaluation", &evaluation},
                                                              {"status", &status},
                                                              {"status_detail", &detail},
                                                              {"health", &health},
                                                              {"excluded", &excluded},
                                                              {"body_plan", &plan},
                                                              {"phenotype_digest", &digest}})
    h5::write_strings(c, g.id(), name, *v);
  h5::write(c, g.id(), "seed", seed);
  h5::write(c, g.id(), "champion_id", id);
  h5::write(c, g.id(), "robustness_seed", rseed);
  h5::write(c, g.id(), "generation", generation);
  h5::write(c, g.id(), "voxels", voxels);
  h5::write(c, g.id(), "input", input);
  h5::write(c, g.id(), "valid_draws", valid);
  using Reals = std::pair<const char*, const std::vector<double>*>;
  for (const auto& [name, v] : std::initializer_list<Reals>{{"fitness", &fitness},
                                                            {"f_train", &f_train},
                                                            {"r_mean", &r_mean},
                                                            {"m_body", &m_body},
                                                            {"v_body", &v_body},
                                                            {"v_gain", &v_gain},
                                                            {"body_plan_confidence", &confidence},
                                                            {"floor_depth", &depth},
                                                            {"vertical_share", &vertical}})
    h5::write(c, g.id(), name, *v);
  h5::write(c, g.id(), "r_draws", r_draw, {n, draws});
  h5::write(c, g.id(), "f_test", f_test, {n, draws});
  // Robustness is a ratio of fitnesses; the body measures are relative changes of E.
  for (const auto& [name, units] : {std::pair{"fitness", "voxel lengths"},
                                    {"f_train", "voxel lengths"},
                                    {"f_test", "voxel lengths"},
                                    {"r_mean", "1"},
                                    {"r_draws", "1"},
                                    {"m_body", "1"},
                                    {"v_body", "1"},
                                    {"v_gain", "1"}})
    h5::write_units(c, g.id(), name, units);
}

void write_hausdorff(const Ctx& c, hid_t root, const StudyResult& r) {
  const HausdorffMatrix& m = r.hausdorff;
  Handle g = h5::create_group(c, root, "hausdorff");
  h5::write_attr(c, g.id(), "rotations", std::string(to_string(m.options.rotations)));
  h5::write_attr(c, g.id(), "translation", std::string(to_string(m.options.translation)));
  h5::write_attr(c, g.id(), "units", std::string("voxel lengths"));
  std::vector<std::string> labels;
  for (const ChampionAnalysis& ch : r.champions) labels.push_back(ch.label);
  h5::write_strings(c, g.id(), "labels", labels);
  const hsize_t n = static_cast<hsize_t>(m.n);
  h5::write(c, g.id(), "matrix", m.distance, {n, n});
  h5::write_units(c, g.id(), "matrix", "voxel lengths");
  // Placement of B (the later champion of each pair): b -> rotation * b + translation.
  std::vector<int32_t> pa, pb, rot, trans;
  std::vector<std::string> rot_name;
  size_t k = 0;
  for (int i = 0; i < m.n; ++i)
    for (int j = i + 1; j < m.n; ++j, ++k) {
      const HausdorffResult& h = m.pairs[k];
      pa.push_back(i);
      pb.push_back(j);
      rot.push_back(h.rotation_index);
      rot_name.push_back(h.rotation.name);
      for (int x : h.translation) trans.push_back(x);
    }
  h5::write(c, g.id(), "pair_a", pa);
  h5::write(c, g.id(), "pair_b", pb);
  h5::write(c, g.id(), "pair_rotation_index", rot);
  h5::write_strings(c, g.id(), "pair_rotation", rot_name);
  h5::write(c, g.id(), "pair_translation", trans, {pa.size(), 3});
}

void write_panels(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle all = h5::create_group(c, root, "panels");
  for (const PanelStats& p : r.panels) {
    Handle g = h5::create_group(c, all.id(), p.id);
    h5::write_attr(c, g.id(), "metric", p.metric);
    h5::write_attr(c, g.id(), "title", p.title);
    h5::write_attr(c, g.id(), "unit", p.unit);
    h5::write_attr(c, g.id(), "comparisons_made", static_cast<int64_t>(p.comparisons.size()));
    h5::write_attr_u64(c, g.id(), "seed", p.seed);
    std::vector<std::string> treatment;
    std::vector<int32_t> count;
    std::vector<double> mean, lo, hi;
    Handle values = h5::create_group(c, g.id(), "values");
    for (const GroupStats& s : p.groups) {
      treatment.push_back(to_string(s.treatment));
      count.push_back(static_cast<int32_t>(s.values.size()));
      mean.push_back(value(s.mean));
      lo.push_back(s.ci ? s.ci->lower : kUndefined);
      hi.push_back(s.ci ? s.ci->upper : kUndefined);
      h5::write(c, values.id(), to_string(s.treatment), s.values);
      h5::write_units(c, values.id(), to_string(s.treatment), p.unit);
    }
    h5::write_strings(c, g.id(), "treatment", treatment);
    h5::write(c, g.id(), "n", count);
    h5::write(c, g.id(), "mean", mean);
    h5::write(c, g.id(), "ci_low", lo);
    h5::write(c, g.id(), "ci_high", hi);
    for (const char* name : {"mean", "ci_low", "ci_high"}) h5::write_units(c, g.id(), name, p.unit);
    std::vector<std::string> a, b, stars;
    std::vector<double> diff, pv, pc, es;
    for (const BootstrapTestResult& t : p.comparisons) {
      a.push_back(t.name_a);
      b.push_back(t.name_b);
      stars.push_back(t.stars);
      diff.push_back(t.difference);
      pv.push_back(t.p_value);
      pc.push_back(t.p_corrected);
      es.push_back(t.effect.hedges_g);
    }
    Handle cg = h5::create_group(c, g.id(), "comparisons");
    h5::write_strings(c, cg.id(), "a", a);
    h5::write_strings(c, cg.id(), "b", b);
    h5::write_strings(c, cg.id(), "stars", stars);
    h5::write(c, cg.id(), "mean_diff", diff);
    h5::write(c, cg.id(), "p", pv);
    h5::write(c, cg.id(), "p_corrected", pc);
    h5::write(c, cg.id(), "effect_size", es);
  }
}

void write_root(const Ctx& c, hid_t root, const StudyResult& r) {
  h5::write_attr(c, root, "format", std::string("plastivox-analysis"));
  h5::write_attr(c, root, "format_version", static_cast<int64_t>(kStudyFormatVersion));
  h5::write_attr(c, root, "plastivox_version", r.version);
  h5::write_attr(c, root, "git_commit", r.commit);
  h5::write_attr(c, root, "date", r.date);
  h5::write_attr(c, root, "command", r.options.command);
  h5::write_attr(c, root, "options", options_json(r.options));
  h5::write_attr(c, root, "fingerprint", r.fingerprint);
  h5::write_attr(c, root, "sinking_rule", r.sinking_rule);
  h5::write_attr(c, root, "fitness_direction", r.fitness_direction);
  h5::write_attr(c, root, "threads", static_cast<int64_t>(r.options.threads));
  const Provenance build = current_provenance(r.options.threads);
  h5::write_attr(c, root, "compiler", build.compiler);
  h5::write_attr(c, root, "build_type", build.build_type);
  h5::write_attr(c, root, "host", build.host);
  const StudyTimings& t = r.timings;
  using Seconds = std::pair<const char*, double>;
  for (const auto& [name, s] :
       std::initializer_list<Seconds>{{"seconds_load", t.load},
                                      {"seconds_robustness", t.robustness},
                                      {"seconds_canalization", t.canalization},
                                      {"seconds_body_plans", t.body_plans},
                                      {"seconds_hausdorff", t.hausdorff},
                                      {"seconds_statistics", t.statistics},
                                      {"seconds_total", t.total}})
    h5::write_attr(c, root, name, s);
  h5::write_attr(c, root, "robustness_simulations", static_cast<int64_t>(t.robustness_simulations));
  h5::write_attr(c, root, "robustness_from_checkpoint", static_cast<int64_t>(t.robustness_cached));
  h5::write_strings(c, root, "warnings", r.warnings);
  h5::write_strings(c, root, "stats_json", {stats_json(r)});
}

// ---- reading back ----

std::optional<double> defined(double x) {
  return std::isnan(x) ? std::nullopt : std::optional<double>(x);
}

// The length of a one-dimensional dataset of any type (the typed reads then check the rest).
size_t extent(const Ctx& c, hid_t loc, const std::string& name) {
  if (!h5::has_link(loc, name)) c.fail(name, "missing");
  Handle d(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), Handle::Kind::kDataset);
  if (d.id() < 0) c.fail(name, "cannot open dataset (not a dataset, or corrupt)");
  Handle space(H5Dget_space(d.id()), Handle::Kind::kDataspace);
  hsize_t n = 0;
  if (space.id() < 0 || H5Sget_simple_extent_ndims(space.id()) != 1 ||
      H5Sget_simple_extent_dims(space.id(), &n, nullptr) != 1)
    c.fail(name, "expected a one-dimensional dataset");
  return n;
}

// The columns of one group, each a dataset of n entries.
struct Columns {
  const Ctx& c;
  hid_t group;
  size_t n;
  std::vector<std::string> strings(const char* name) const {
    return h5::read_strings(c, group, name, n);
  }
  std::vector<double> reals(const char* name) const { return h5::read<double>(c, group, name, n); }
  std::vector<int32_t> ints(const char* name) const { return h5::read<int32_t>(c, group, name, n); }
  std::vector<uint64_t> words(const char* name) const {
    return h5::read<uint64_t>(c, group, name, n);
  }
};

template <class E>
E parse_name(const Ctx& c, const std::string& object, const std::string& name,
             std::initializer_list<E> values) {
  for (E v : values)
    if (name == to_string(v)) return v;
  c.fail(object, "unknown value '" + name + "'");
}

// The options from their JSON; they must print back to the very text stored, so a field this
// build does not know is refused rather than dropped.
StudyOptions read_options(const Ctx& c, hid_t root) {
  const std::string text = h5::read_attr_string(c, root, "/", "options");
  StudyOptions o;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    o.generation = j.at("generation").is_string() ? -1 : j.at("generation").get<int>();
    o.robustness_draws = j.at("robustness_draws").get<int>();
    o.robustness_sampling = j.at("robustness_sampling").get<std::string>() == "linear"
                                ? StiffnessDistribution::kLinear
                                : StiffnessDistribution::kLogUniform;
    o.rotations = parse_rotation_search(j.at("rotations").get<std::string>());
    o.translation = j.at("translation").get<std::string>() == to_string(TranslationSearch::kNone)
                        ? TranslationSearch::kNone
                        : TranslationSearch::kInteger;
    o.resamples = j.at("resamples").get<int>();
    o.seed = j.at("seed").get<uint64_t>();
    o.alpha = j.at("alpha").get<double>();
    o.ci_level = j.at("ci_level").get<double>();
    o.allow_mixed_physics = j.at("allow_mixed_physics").get<bool>();
    o.keep_artifacts = j.at("keep_artifacts").get<bool>();
    for (const auto& t : j.at("treatments")) o.treatments.push_back(parse_treatment(t));
  } catch (const std::exception& e) {
    c.fail("/@options", std::string("not understood (") + e.what() + ")");
  }
  if (options_json(o) != text) c.fail("/@options", "not understood (fields this build lacks)");
  o.command = h5::read_attr_string(c, root, "/", "command");
  o.threads = static_cast<int>(h5::read_attr_int(c, root, "/", "threads"));
  return o;
}

void read_inputs(const Ctx& c, hid_t root, StudyResult& r) {
  Handle g = h5::open_group(c, root, "inputs");
  const size_t n = extent(c, g.id(), "seed");
  const Columns col{c, g.id(), n};
  const auto file = col.strings("file"), digest = col.strings("content_digest"),
             treatment = col.strings("treatment"), physics = col.strings("physics_json");
  const auto seed = col.words("seed");
  const auto generation = col.ints("generation"), done = col.ints("generations_done"),
             body_plans = col.ints("body_plan_start");
  for (size_t i = 0; i < n; ++i) {
    StudyInput in;
    in.file = file[i];
    in.content_digest = digest[i];
    in.treatment = parse_treatment(treatment[i]);
    in.physics_json = physics[i];
    in.seed = seed[i];
    in.generation = generation[i];
    in.generations_done = done[i];
    in.body_plan_start = body_plans[i] != 0;
    r.inputs.push_back(std::move(in));
  }
}

void read_champions(const Ctx& c, hid_t root, StudyResult& r) {
  Handle g = h5::open_group(c, root, "champions");
  const hid_t id = g.id();
  const size_t n = extent(c, id, "input");
  const size_t draws = static_cast<size_t>(r.options.robustness_draws);
  const Columns col{c, id, n};
  const auto label = col.strings("label"), treatment = col.strings("treatment"),
             evaluation = col.strings("evaluation"), status = col.strings("status"),
             detail = col.strings("status_detail"), health = col.strings("health"),
             excluded = col.strings("excluded"), plan = col.strings("body_plan"),
             digest = col.strings("phenotype_digest");
  const auto seed = col.words("seed"), champion_id = col.words("champion_id"),
             robustness_seed = col.words("robustness_seed");
  const auto generation = col.ints("generation"), voxels = col.ints("voxels"),
             input = col.ints("input"), valid = col.ints("valid_draws");
  const auto fitness = col.reals("fitness"), f_train = col.reals("f_train"),
             r_mean = col.reals("r_mean"), m_body = col.reals("m_body"),
             v_body = col.reals("v_body"), v_gain = col.reals("v_gain"),
             confidence = col.reals("body_plan_confidence"), depth = col.reals("floor_depth"),
             vertical = col.reals("vertical_share");
  std::vector<hsize_t> shape{n, draws};
  const auto r_draws = h5::read<double>(c, id, "r_draws", shape);
  const auto f_test = h5::read<double>(c, id, "f_test", shape);
  for (size_t i = 0; i < n; ++i) {
    ChampionAnalysis ch;
    ch.label = label[i];
    ch.treatment = parse_treatment(treatment[i]);
    ch.evaluation = evaluation[i];
    ch.status = status[i];
    ch.status_detail = detail[i];
    ch.health = health[i];
    ch.artifact = excluded[i];
    ch.body_plan.plan =
        parse_name(c, "/champions/body_plan", plan[i],
                   {BodyPlan::kPi, BodyPlan::kGamma, BodyPlan::kUpsilon, BodyPlan::kOther});
    ch.body_plan.confidence = confidence[i];
    ch.phenotype_digest = digest[i];
    ch.run_seed = seed[i];
    ch.id = champion_id[i];
    ch.robustness_seed = robustness_seed[i];
    ch.generation = generation[i];
    ch.voxels = voxels[i];
    ch.input = input[i];
    if (ch.input < 0 || static_cast<size_t>(ch.input) >= r.inputs.size())
      c.fail("/champions/input", "entry " + std::to_string(i) + " names no input");
    ch.fitness = std::isnan(fitness[i]) ? 0 : fitness[i];
    ch.robustness.valid_draws = valid[i];
    ch.robustness.train_valid = !std::isnan(f_train[i]);
    ch.robustness.f_train = ch.robustness.train_valid ? f_train[i] : 0;
    for (size_t k = 0; k < draws; ++k) {
      RobustnessDraw d;
      d.valid = !std::isnan(f_test[i * draws + k]);
      if (d.valid) {
        d.r = r_draws[i * draws + k];
        d.f_test = f_test[i * draws + k];
      }
      ch.robustness.draws.push_back(d);
    }
    ch.r_mean = defined(r_mean[i]);
    ch.m_body = defined(m_body[i]);
    ch.v_body = defined(v_body[i]);
    ch.v_gain = defined(v_gain[i]);
    ch.floor_depth = depth[i];
    ch.vertical_share = vertical[i];
    // Champions are sorted by treatment: the treatments present, in their order.
    if (r.treatments.empty() || r.treatments.back() != ch.treatment)
      r.treatments.push_back(ch.treatment);
    r.champions.push_back(std::move(ch));
  }
}

void read_hausdorff(const Ctx& c, hid_t root, StudyResult& r) {
  Handle g = h5::open_group(c, root, "hausdorff");
  HausdorffMatrix& m = r.hausdorff;
  m.n = static_cast<int>(r.champions.size());
  m.options.rotations = r.options.rotations;
  m.options.translation = r.options.translation;
  const hsize_t n = r.champions.size();
  std::vector<hsize_t> shape{n, n};
  m.distance = h5::read<double>(c, g.id(), "matrix", shape);
}

void read_panels(const Ctx& c, hid_t root, StudyResult& r) {
  Handle all = h5::open_group(c, root, "panels");
  for (char letter = 'A'; letter <= 'Z'; ++letter) {
    const std::string name(1, letter);
    if (!h5::has_link(all.id(), name)) continue;
    Handle g = h5::open_group(c, all.id(), name);
    const std::string where = "/panels/" + name;
    PanelStats p;
    p.id = name;
    p.metric = h5::read_attr_string(c, g.id(), where, "metric");
    p.title = h5::read_attr_string(c, g.id(), where, "title");
    p.unit = h5::read_attr_string(c, g.id(), where, "unit");
    p.seed = h5::read_attr_u64(c, g.id(), where, "seed");
    const int comparisons =
        static_cast<int>(h5::read_attr_int(c, g.id(), where, "comparisons_made"));
    const Columns col{c, g.id(), extent(c, g.id(), "n")};
    const size_t groups = col.n;
    const auto treatment = col.strings("treatment");
    const auto mean = col.reals("mean"), lo = col.reals("ci_low"), hi = col.reals("ci_high");
    const auto count = col.ints("n");
    Handle values = h5::open_group(c, g.id(), "values");
    for (size_t k = 0; k < groups; ++k) {
      GroupStats s;
      s.treatment = parse_treatment(treatment[k]);
      s.values = h5::read<double>(c, values.id(), treatment[k],
                                  static_cast<hsize_t>(std::max(count[k], 0)));
      s.mean = defined(mean[k]);
      if (!std::isnan(lo[k])) {
        ConfidenceInterval ci;
        ci.level = r.options.ci_level;
        ci.resamples = r.options.resamples;
        ci.n = count[k];
        ci.mean = mean[k];
        ci.lower = lo[k];
        ci.upper = hi[k];
        s.ci = ci;
      }
      p.groups.push_back(std::move(s));
    }
    Handle cg = h5::open_group(c, g.id(), "comparisons");
    const Columns tests{c, cg.id(), extent(c, cg.id(), "p")};
    const auto a = tests.strings("a"), b = tests.strings("b"), stars = tests.strings("stars");
    const auto diff = tests.reals("mean_diff"), pv = tests.reals("p"),
               pc = tests.reals("p_corrected"), es = tests.reals("effect_size");
    for (size_t k = 0; k < tests.n; ++k) {
      BootstrapTestResult t;
      t.name_a = a[k];
      t.name_b = b[k];
      t.stars = stars[k];
      t.difference = diff[k];
      t.p_value = pv[k];
      t.p_corrected = pc[k];
      t.effect.hedges_g = es[k];
      t.comparisons = comparisons;
      p.comparisons.push_back(std::move(t));
    }
    r.panels.push_back(std::move(p));
  }
}

}  // namespace

void write_analysis_h5(const StudyResult& r, const std::string& final_path,
                       const std::string& path) {
  const Ctx c{final_path, 0};
  std::string bytes;
  {
    h5::MemoryFile f(c, 0);  // built in memory: a full disk never reaches HDF5
    {
      Handle root = h5::open_group(c, f.id(), "/");
      write_root(c, root.id(), r);
      write_inputs(c, root.id(), r);
      write_champions(c, root.id(), r);
      write_hausdorff(c, root.id(), r);
      write_panels(c, root.id(), r);
    }
    bytes = f.image();
  }
  write_file_atomic(path, bytes);
}

}  // namespace plastivox::analysis::study

namespace plastivox::analysis {

StudyResult read_study_result(const std::string& path) {
  using h5::Ctx;
  using h5::Handle;
  const Ctx c = h5::read_context(path);
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw std::runtime_error(path + ": not an HDF5 file (wrong format, or corrupt or truncated)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Handle::Kind::kFile);
  if (f.id() < 0) throw std::runtime_error(path + ": cannot open as HDF5 (corrupt or truncated)");
  Handle root = h5::open_group(c, f.id(), "/");
  const hid_t r = root.id();
  if (!h5::has_attr(r, "format") ||
      h5::read_attr_string(c, r, "/", "format") != "plastivox-analysis")
    throw std::runtime_error(path +
                             ": not a plastivox analysis (no format attribute "
                             "\"plastivox-analysis\" on /)");
  const int64_t version = h5::read_attr_int(c, r, "/", "format_version");
  if (version != kStudyFormatVersion)
    throw std::runtime_error(path + ": analysis format version " + std::to_string(version) +
                             " is not the one this build reads (" +
                             std::to_string(kStudyFormatVersion) + ")");
  StudyResult s;
  s.options = study::read_options(c, r);
  s.version = h5::read_attr_string(c, r, "/", "plastivox_version");
  s.commit = h5::read_attr_string(c, r, "/", "git_commit");
  s.date = h5::read_attr_string(c, r, "/", "date");
  s.fingerprint = h5::read_attr_string(c, r, "/", "fingerprint");
  s.sinking_rule = h5::read_attr_string(c, r, "/", "sinking_rule");
  s.fitness_direction = h5::read_attr_string(c, r, "/", "fitness_direction");
  s.warnings = h5::read_strings(c, r, "warnings", study::extent(c, r, "warnings"));
  study::read_inputs(c, r, s);
  study::read_champions(c, r, s);
  study::read_hausdorff(c, r, s);
  study::read_panels(c, r, s);
  return s;
}

}  // namespace plastivox::analysis
