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

// The fields stored as the records hold them, as f(name, member): the writer and the reader
// both walk these lists (the fields that need converting are written and read beside them).
template <class F>
void for_each_input_column(F&& f) {
  f("file", &StudyInput::file);
  f("content_digest", &StudyInput::content_digest);
  f("physics_json", &StudyInput::physics_json);
  f("seed", &StudyInput::seed);
  f("generation", &StudyInput::generation);
  f("generations_done", &StudyInput::generations_done);
}

template <class F>
void for_each_champion_column(F&& f) {
  using Ch = ChampionAnalysis;
  f("label", &Ch::label);
  f("evaluation", &Ch::evaluation);
  f("status", &Ch::status);
  f("status_detail", &Ch::status_detail);
  f("health", &Ch::health);
  f("excluded", &Ch::artifact);
  f("phenotype_digest", &Ch::phenotype_digest);
  f("seed", &Ch::run_seed);
  f("champion_id", &Ch::id);
  f("robustness_seed", &Ch::robustness_seed);
  f("generation", &Ch::generation);
  f("voxels", &Ch::voxels);
  f("input", &Ch::input);
  f("floor_depth", &Ch::floor_depth);
  f("vertical_share", &Ch::vertical_share);
}

template <class F>
void for_each_comparison_column(F&& f) {
  using Test = BootstrapTestResult;
  f("a", &Test::name_a);
  f("b", &Test::name_b);
  f("stars", &Test::stars);
  f("mean_diff", &Test::difference);
  f("p", &Test::p_value);
  f("p_corrected", &Test::p_corrected);
}

void write_inputs(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle g = h5::create_group(c, root, "inputs");
  const std::vector<StudyInput>& in = r.inputs;
  for_each_input_column(
      [&](const char* name, auto member) { h5::write_column(c, g.id(), name, in, member); });
  h5::write_column<std::string>(c, g.id(), "treatment", in,
                                [](const StudyInput& i) { return to_string(i.treatment); });
  h5::write_column<int32_t>(c, g.id(), "body_plan_start", in, &StudyInput::body_plan_start);
}

void write_champions(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle g = h5::create_group(c, root, "champions");
  using Ch = ChampionAnalysis;
  const std::vector<Ch>& all = r.champions;
  const hid_t id = g.id();
  for_each_champion_column(
      [&](const char* name, auto member) { h5::write_column(c, id, name, all, member); });
  h5::write_column<std::string>(c, id, "treatment", all,
                                [](const Ch& ch) { return to_string(ch.treatment); });
  h5::write_column<std::string>(c, id, "body_plan", all,
                                [](const Ch& ch) { return to_string(ch.body_plan.plan); });
  h5::write_column<int32_t>(c, id, "valid_draws", all,
                            [](const Ch& ch) { return ch.robustness.valid_draws; });
  h5::write_column<int32_t>(c, id, "vertical_exploit", all,
                            [](const Ch& ch) { return ch.vertical_exploit ? 1 : 0; });
  // Undefined values are NaN.
  h5::write_column<double>(c, id, "fitness", all, [](const Ch& ch) {
    return ch.evaluation == "ok" ? ch.fitness : kUndefined;
  });
  h5::write_column<double>(c, id, "f_train", all, [](const Ch& ch) {
    return ch.robustness.train_valid ? ch.robustness.f_train : kUndefined;
  });
  for (const auto& [name, member] : {std::pair{"r_mean", &Ch::r_mean},
                                     {"m_body", &Ch::m_body},
                                     {"v_body", &Ch::v_body},
                                     {"v_gain", &Ch::v_gain}})
    h5::write_column<double>(c, id, name, all, [m = member](const Ch& ch) { return value(ch.*m); });
  h5::write_column<double>(c, id, "body_plan_confidence", all,
                           [](const Ch& ch) { return ch.body_plan.confidence; });
  // Per champion and robustness draw: (champions, draws).
  const size_t n = all.size(), draws = static_cast<size_t>(r.options.robustness_draws);
  std::vector<double> r_draw(n * draws, kUndefined), f_test(n * draws, kUndefined);
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < all[i].robustness.draws.size() && k < draws; ++k) {
      const RobustnessDraw& d = all[i].robustness.draws[k];
      if (!d.valid) continue;
      r_draw[i * draws + k] = d.r;
      f_test[i * draws + k] = d.f_test;
    }
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
  h5::write_column(c, g.id(), "labels", r.champions, &ChampionAnalysis::label);
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

void write_panel(const Ctx& c, hid_t all, const PanelStats& p) {
  {
    Handle g = h5::create_group(c, all, p.id);
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
    using Test = BootstrapTestResult;
    const std::vector<Test>& tests = p.comparisons;
    Handle cg = h5::create_group(c, g.id(), "comparisons");
    for_each_comparison_column(
        [&](const char* name, auto member) { h5::write_column(c, cg.id(), name, tests, member); });
    h5::write_column<double>(c, cg.id(), "effect_size", tests,
                             [](const Test& t) { return t.effect.hedges_g; });
  }
}

void write_panels(const Ctx& c, hid_t root, const StudyResult& r) {
  Handle all = h5::create_group(c, root, "panels");
  for (const PanelStats& p : r.panels) write_panel(c, all.id(), p);
}

// /battery (only with a battery): the battery as JSON, one row per champion x perturbation x
// severity, and per perturbation its AUC compared between treatments (panels P1, P2, ...).
void write_battery(const Ctx& c, hid_t root, const StudyResult& r) {
  if (!r.battery) return;
  Handle g = h5::create_group(c, root, "battery");
  h5::write_attr(c, g.id(), "battery", battery_json(*r.battery));
  h5::write_attr(c, g.id(), "name", r.battery->name);
  h5::write_attr(c, g.id(), "lives", static_cast<int64_t>(r.battery_lives));
  h5::write_attr(c, g.id(), "unstable", static_cast<int64_t>(r.battery_unstable));
  h5::write_attr(c, g.id(), "sank", static_cast<int64_t>(r.battery_sank));
  std::vector<std::string> champion, perturbation, kind, unit;
  std::vector<double> severity, mean, sd, auc, reference;
  std::vector<int32_t> lives, valid, unstable, sank;
  for (const ChampionAnalysis& ch : r.champions) {
    if (!ch.profile) continue;
    for (const PerturbationProfile& p : ch.profile->perturbations)
      for (const SeverityLevel& l : p.levels) {
        champion.push_back(ch.label);
        perturbation.push_back(p.name);
        kind.push_back(to_string(p.kind));
        unit.push_back(p.unit);
        severity.push_back(l.severity);
        mean.push_back(value(l.mean_kept));
        sd.push_back(value(l.sd_kept));
        auc.push_back(value(p.auc));
        reference.push_back(p.reference_valid ? p.f_reference : kUndefined);
        lives.push_back(static_cast<int32_t>(l.lives.size()));
        valid.push_back(l.valid);
        unstable.push_back(l.unstable);
        sank.push_back(l.sank);
      }
  }
  Handle t = h5::create_group(c, g.id(), "profiles");
  h5::write_strings(c, t.id(), "champion", champion);
  h5::write_strings(c, t.id(), "perturbation", perturbation);
  h5::write_strings(c, t.id(), "kind", kind);
  h5::write_strings(c, t.id(), "severity_unit", unit);
  h5::write(c, t.id(), "severity", severity);
  h5::write_units(c, t.id(), "severity", "the row's severity_unit");
  for (const auto& [name, column] :
       {std::pair<const char*, const std::vector<double>*>{"mean_kept", &mean},
        {"sd_kept", &sd},
        {"auc", &auc}}) {
    h5::write(c, t.id(), name, *column);
    h5::write_units(c, t.id(), name, "F_perturbed / F_reference (dimensionless)");
  }
  h5::write(c, t.id(), "f_reference", reference);
  h5::write_units(c, t.id(), "f_reference", r.fitness_unit);
  h5::write(c, t.id(), "lives", lives);
  h5::write(c, t.id(), "valid", valid);
  h5::write(c, t.id(), "unstable", unstable);
  h5::write(c, t.id(), "sank", sank);
  Handle all = h5::create_group(c, g.id(), "panels");
  for (const PanelStats& p : r.battery_panels) write_panel(c, all.id(), p);
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
  h5::write_attr(c, root, "task", r.task);
  h5::write_attr(c, root, "fitness_unit", r.fitness_unit);
  h5::write_attr(c, root, "environment", r.environment);
  h5::write_attr(c, root, "controller", r.controller);
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
  bool vertical_known = false;
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
    // Absent in files written before the vertical rule: nothing was flagged then.
    vertical_known = j.contains("keep_vertical");
    o.keep_vertical = vertical_known && j.at("keep_vertical").get<bool>();
    for (const auto& t : j.at("treatments")) o.treatments.push_back(parse_treatment(t));
    if (j.contains("battery")) o.battery = j.at("battery").get<std::string>();
  } catch (const std::exception& e) {
    c.fail("/@options", std::string("not understood (") + e.what() + ")");
  }
  nlohmann::ordered_json expect = nlohmann::ordered_json::parse(options_json(o));
  if (!vertical_known) expect.erase("keep_vertical");
  if (expect.dump() != text) c.fail("/@options", "not understood (fields this build lacks)");
  o.command = h5::read_attr_string(c, root, "/", "command");
  o.threads = static_cast<int>(h5::read_attr_int(c, root, "/", "threads"));
  return o;
}

void read_inputs(const Ctx& c, hid_t root, StudyResult& r) {
  Handle g = h5::open_group(c, root, "inputs");
  std::vector<StudyInput>& in = r.inputs;
  in.resize(extent(c, g.id(), "seed"));
  for_each_input_column(
      [&](const char* name, auto member) { h5::read_column(c, g.id(), name, in, member); });
  const Columns col{c, g.id(), in.size()};
  const auto treatment = col.strings("treatment");
  const auto body_plans = col.ints("body_plan_start");
  for (size_t i = 0; i < in.size(); ++i) {
    in[i].treatment = parse_treatment(treatment[i]);
    in[i].body_plan_start = body_plans[i] != 0;
  }
}

void read_champions(const Ctx& c, hid_t root, StudyResult& r) {
  Handle g = h5::open_group(c, root, "champions");
  const hid_t id = g.id();
  using Ch = ChampionAnalysis;
  std::vector<Ch> all(extent(c, id, "input"));
  const size_t n = all.size(), draws = static_cast<size_t>(r.options.robustness_draws);
  for_each_champion_column(
      [&](const char* name, auto member) { h5::read_column(c, id, name, all, member); });
  const Columns col{c, id, n};
  const auto treatment = col.strings("treatment"), plan = col.strings("body_plan");
  const auto valid = col.ints("valid_draws");
  // Absent in files written before the vertical rule, which flagged nothing.
  const auto vertical = H5Lexists(id, "vertical_exploit", H5P_DEFAULT) > 0
                            ? col.ints("vertical_exploit")
                            : std::vector<int32_t>(n, 0);
  const auto fitness = col.reals("fitness"), f_train = col.reals("f_train"),
             r_mean = col.reals("r_mean"), m_body = col.reals("m_body"),
             v_body = col.reals("v_body"), v_gain = col.reals("v_gain"),
             confidence = col.reals("body_plan_confidence");
  std::vector<hsize_t> shape{n, draws};
  const auto r_draws = h5::read<double>(c, id, "r_draws", shape);
  const auto f_test = h5::read<double>(c, id, "f_test", shape);
  for (size_t i = 0; i < n; ++i) {
    Ch& ch = all[i];
    ch.treatment = parse_treatment(treatment[i]);
    ch.body_plan.plan =
        parse_name(c, "/champions/body_plan", plan[i],
                   {BodyPlan::kPi, BodyPlan::kGamma, BodyPlan::kUpsilon, BodyPlan::kOther});
    ch.body_plan.confidence = confidence[i];
    ch.vertical_exploit = vertical[i] != 0;
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
    // Champions are sorted by treatment: the treatments present, in their order.
    if (r.treatments.empty() || r.treatments.back() != ch.treatment)
      r.treatments.push_back(ch.treatment);
  }
  r.champions = std::move(all);
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

PanelStats read_panel(const Ctx& c, hid_t all, const std::string& name, const std::string& where,
                      const StudyResult& r) {
  {
    Handle g = h5::open_group(c, all, name);
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
    using Test = BootstrapTestResult;
    std::vector<Test> tests(extent(c, cg.id(), "p"));
    for_each_comparison_column(
        [&](const char* name, auto member) { h5::read_column(c, cg.id(), name, tests, member); });
    const auto es = h5::read<double>(c, cg.id(), "effect_size", tests.size());
    for (size_t k = 0; k < tests.size(); ++k) {
      tests[k].effect.hedges_g = es[k];
      tests[k].comparisons = comparisons;
    }
    p.comparisons = std::move(tests);
    return p;
  }
}

void read_panels(const Ctx& c, hid_t root, StudyResult& r) {
  Handle all = h5::open_group(c, root, "panels");
  for (char letter = 'A'; letter <= 'Z'; ++letter) {
    const std::string name(1, letter);
    if (h5::has_link(all.id(), name))
      r.panels.push_back(read_panel(c, all.id(), name, "/panels/" + name, r));
  }
}

// The battery and its panels (the profiles stay in the file: the report draws the panels).
void read_battery(const Ctx& c, hid_t root, StudyResult& r) {
  if (!h5::has_link(root, "battery")) return;
  Handle g = h5::open_group(c, root, "battery");
  try {
    r.battery = parse_battery(h5::read_attr_string(c, g.id(), "/battery", "battery"),
                              h5::read_attr_string(c, g.id(), "/battery", "name"));
  } catch (const std::invalid_argument& e) {
    c.fail("/battery@battery", e.what());
  }
  r.battery_lives = static_cast<int>(h5::read_attr_int(c, g.id(), "/battery", "lives"));
  r.battery_unstable = static_cast<int>(h5::read_attr_int(c, g.id(), "/battery", "unstable"));
  r.battery_sank = static_cast<int>(h5::read_attr_int(c, g.id(), "/battery", "sank"));
  Handle all = h5::open_group(c, g.id(), "panels");
  for (size_t k = 1; k <= r.battery->perturbations.size(); ++k) {
    const std::string name = "P" + std::to_string(k);
    r.battery_panels.push_back(read_panel(c, all.id(), name, "/battery/panels/" + name, r));
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
      write_battery(c, root.id(), r);
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
  if (h5::has_attr(r, "task")) {  // absent in files written before tasks: walk
    s.task = h5::read_attr_string(c, r, "/", "task");
    s.fitness_unit = h5::read_attr_string(c, r, "/", "fitness_unit");
  }
  if (h5::has_attr(r, "environment"))  // absent in files written before environments
    s.environment = h5::read_attr_string(c, r, "/", "environment");
  if (h5::has_attr(r, "controller"))  // absent in files written before: load_champion_bodies
    s.controller = h5::read_attr_string(c, r, "/", "controller");
  s.warnings = h5::read_strings(c, r, "warnings", study::extent(c, r, "warnings"));
  study::read_inputs(c, r, s);
  study::read_champions(c, r, s);
  study::read_hausdorff(c, r, s);
  study::read_panels(c, r, s);
  study::read_battery(c, r, s);
  return s;
}

}  // namespace plastivox::analysis
