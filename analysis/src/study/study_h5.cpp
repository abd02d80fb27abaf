// analysis.h5: the study's results in HDF5 (layout in docs/analysis.md, "analysis.h5"), with the
// same content as stats.json plus provenance, per-pair placements and timings. Undefined values
// are NaN here (HDF5 has no null). Uses the evolver's checked HDF5 wrappers (h5_util.hpp), so
// every failure is one line naming the file and the object.
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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
  std::vector<int32_t> generation, done;
  for (const StudyInput& in : r.inputs) {
    file.push_back(in.file);
    digest.push_back(in.content_digest);
    treatment.push_back(to_string(in.treatment));
    physics.push_back(in.physics_json);
    seed.push_back(in.seed);
    generation.push_back(in.generation);
    done.push_back(in.generations_done);
  }
  h5::write_strings(c, g.id(), "file", file);
  h5::write_strings(c, g.id(), "content_digest", digest);
  h5::write_strings(c, g.id(), "treatment", treatment);
  h5::write_strings(c, g.id(), "physics_json", physics);
  h5::write(c, g.id(), "seed", seed);
  h5::write(c, g.id(), "generation", generation);
  h5::write(c, g.id(), "generations_done", done);
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
