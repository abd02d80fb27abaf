// Experiment config: parsing, validation, canonical forms, embedded presets.
#include "experiment_config.hpp"

#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "experiment_presets.hpp"  // generated from assets/presets/experiment-*.json
#include "plastivox/analysis/battery.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/panels.hpp"

namespace plastivox::experiment {
namespace {

using nlohmann::json;

using json_field::boolean;
using json_field::fail;
using json_field::integer;

std::string text(const json& j, const std::string& src, const std::string& field,
                 const std::set<std::string>& allowed) {
  std::string all;
  for (const auto& a : allowed) all += (all.empty() ? "" : " | ") + a;
  if (!j.is_string()) fail(src, field, "expected a string (" + all + ")");
  const auto v = j.get<std::string>();
  if (!allowed.empty() && !allowed.count(v)) fail(src, field, "'" + v + "' is not one of " + all);
  return v;
}

// "1280x720" -> (1280, 720), each side in [16, 8192].
void size(const json& j, const std::string& src, const std::string& field, int& w, int& h) {
  if (!j.is_string()) fail(src, field, "expected \"WIDTHxHEIGHT\", e.g. \"1280x720\"");
  const auto s = j.get<std::string>();
  char x = 0, extra = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> h) || x != 'x' || (in >> extra) || w < 16 || h < 16 || w > 8192 || h > 8192)
    fail(src, field, "'" + s + "' is not WIDTHxHEIGHT with sides in [16, 8192]");
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// What the rendering stage would refuse, refused here, before any evolution: the figure
// panels' size (and their combined figure) and a gallery's layout of one treatment's runs.
void check_rendering_sizes(const ExperimentConfig& c, const std::string& src) {
  const RenderSettings& r = c.rendering;
  try {
    if (r.figures) {
      render::FigureOptions fo;
      fo.width = r.figure_width;
      fo.height = r.figure_height;
      render::check_figure_size(fo, 6);  // panels A-F
    }
  } catch (const std::exception& e) {
    fail(src, "rendering.figure_size", e.what());
  }
  try {
    if (r.galleries) {
      render::GalleryStyle style;
      style.width = r.gallery_width;
      style.height = r.gallery_height;
      render::check_gallery_size(style, static_cast<int>(c.seeds.size()));
    }
  } catch (const std::exception& e) {
    fail(src, "rendering.gallery_size", e.what());
  }
}

void parse_analysis(const json& v, const std::string& src, AnalysisSettings& a) {
  if (!v.is_object()) fail(src, "analysis", "expected an object");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string f = "analysis." + it.key();
    if (it.key() == "generation") {
      if (it->is_string() && *it == "last")
        a.generation = -1;
      else
        a.generation = integer(*it, src, f, 0, 100000000);
    } else if (it.key() == "robustness_draws") {
      a.robustness_draws = integer(*it, src, f, 1, 100000);
    } else if (it.key() == "robustness_sampling") {
      a.robustness_sampling = text(*it, src, f, {"linear", "log"});
    } else if (it.key() == "resamples") {
      a.resamples = integer(*it, src, f, 100, 100000000);
    } else if (it.key() == "rotations") {
      a.rotations = text(*it, src, f, {"none", "paper", "all"});
    } else if (it.key() == "translation") {
      a.translation = text(*it, src, f, {"none", "integer"});
    } else if (it.key() == "seed") {
      if (!it->is_number_unsigned()) fail(src, f, "expected a non-negative integer");
      a.seed = it->get<uint64_t>();
    } else if (it.key() == "battery") {
      if (!it->is_string() || it->get<std::string>().empty())
        fail(src, f, "expected default, paper, small or a battery file");
      a.battery = it->get<std::string>();
    } else {
      fail(src, f, "unknown field");
    }
  }
  if (a.battery.empty()) return;
  try {  // a bad battery stops the study here, before any run evolves
    a.battery_lives =
        analysis::battery_lives(analysis::load_battery(a.battery, a.robustness_draws));
  } catch (const std::invalid_argument& e) {
    fail(src, "analysis.battery", e.what());
  }
}

void parse_rendering(const json& v, const std::string& src, RenderSettings& r) {
  if (!v.is_object()) fail(src, "rendering", "expected an object");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string f = "rendering." + it.key();
    if (it.key() == "figures")
      r.figures = boolean(*it, src, f);
    else if (it.key() == "galleries")
      r.galleries = boolean(*it, src, f);
    else if (it.key() == "video")
      r.video = boolean(*it, src, f);
    else if (it.key() == "figure_size")
      size(*it, src, f, r.figure_width, r.figure_height);
    else if (it.key() == "gallery_size")
      size(*it, src, f, r.gallery_width, r.gallery_height);
    else if (it.key() == "video_size")
      size(*it, src, f, r.video_width, r.video_height);
    else if (it.key() == "video_fps") {
      if (!it->is_number() || !(it->get<double>() >= 1 && it->get<double>() <= 240))
        fail(src, f, "expected a number in [1, 240]");
      r.video_fps = it->get<double>();
    } else if (it.key() == "video_color")
      r.video_color = text(*it, src, f, {"congenital", "stiffness", "change", "alpha", "phase"});
    else
      fail(src, f, "unknown field");
  }
}

json canonical(const ExperimentConfig& c, bool with_run_control) {
  json j;
  j["format"] = "plastivox-experiment-config";
  j["version"] = kExperimentConfigVersion;
  j["name"] = c.name;
  json t = json::array();
  for (auto x : c.treatments) t.push_back(to_string(x));
  j["treatments"] = t;
  j["seeds"] = c.seeds;
  json e =
      json::parse(with_run_control ? c.evolution.canonical_json() : c.evolution.identity_json());
  for (const char* k : {"format", "version", "seed", "treatment", "threads"}) e.erase(k);
  j["evolution"] = e;
  const auto& a = c.analysis;
  j["analysis"] = {{"generation", a.generation < 0 ? json("last") : json(a.generation)},
                   {"robustness_draws", a.robustness_draws},
                   {"robustness_sampling", a.robustness_sampling},
                   {"resamples", a.resamples},
                   {"rotations", a.rotations},
                   {"translation", a.translation},
                   {"seed", a.seed}};
  if (!a.battery.empty()) j["analysis"]["battery"] = a.battery;  // absent: the same identity
  const auto& r = c.rendering;
  j["rendering"] = {{"figures", r.figures},
                    {"galleries", r.galleries},
                    {"video", r.video},
                    {"figure_size", size_text(r.figure_width, r.figure_height)},
                    {"gallery_size", size_text(r.gallery_width, r.gallery_height)},
                    {"video_size", size_text(r.video_width, r.video_height)},
                    {"video_fps", r.video_fps},
                    {"video_color", r.video_color}};
  if (with_run_control) j["threads"] = c.threads;
  return j;
}

}  // namespace

std::string ExperimentConfig::run_label(Treatment t, uint64_t seed) {
  return std::string(to_string(t)) + "-s" + std::to_string(seed);
}

evo::EvolveConfig ExperimentConfig::run_config(Treatment t, uint64_t seed) const {
  evo::EvolveConfig c = evolution;
  c.seed = seed;
  c.treatment = t;
  c.physics.treatment = t;
  c.threads = threads;
  return c;
}

int64_t ExperimentConfig::lives_in_generation(int g) const {
  const int64_t p = evolution.population;
  return g == 0 || evolution.algorithm == evo::Algorithm::kMapElites ? p : p + 1;
}

int64_t ExperimentConfig::lives_through(int g) const {
  return lives_in_generation(0) + g * lives_in_generation(1);
}

std::string ExperimentConfig::canonical_json() const {
  return canonical(*this, true).dump();
}
std::string ExperimentConfig::identity_json() const {
  return canonical(*this, false).dump();
}

ExperimentConfig parse_experiment_config(const std::string& input, const std::string& src) {
  json j = parse_json_file(input, src, "plastivox-experiment-config");
  if (!j.contains("version") || !j["version"].is_number_integer() ||
      j["version"].get<int64_t>() != kExperimentConfigVersion)
    fail(src, "version",
         "expected " + std::to_string(kExperimentConfigVersion) + " (this build's version)");

  ExperimentConfig c;
  json evolution = json::object();
  std::optional<GrowthModel> law;  // the law the treatments name, and the first to name it
  std::string law_field;
  json task;  // the top level's "task", when given
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    const json& v = *it;
    if (k == "format" || k == "version" || k == "_comment") {
      continue;
    } else if (k == "name") {
      if (!v.is_string() || v.get<std::string>().empty())
        fail(src, k, "expected a non-empty string");
      c.name = v.get<std::string>();
    } else if (k == "treatments") {
      if (!v.is_array() || v.empty())
        fail(src, k, "expected a non-empty list of treatments (" + treatment_names() + ")");
      c.treatments.clear();
      for (size_t i = 0; i < v.size(); ++i) {
        const std::string f = k + "[" + std::to_string(i) + "]";
        const TreatmentSpec spec = json_field::treatment(v[i], src, f);
        const Treatment t = spec.stimulus;
        // One study compares its treatments under one physics, so one law serves them all.
        if (spec.law) {
          if (law && *law != *spec.law)
            fail(src, f + ".law",
                 std::string("'") + to_string(*spec.law) + "' differs from " + law_field + "'s '" +
                     to_string(*law) + "' (one experiment uses one law for every treatment)");
          if (!law) law_field = f + ".law";
          law = spec.law;
        }
        for (auto seen : c.treatments)
          if (seen == t) fail(src, f, "'" + std::string(to_string(t)) + "' listed twice");
        c.treatments.push_back(t);
      }
    } else if (k == "seeds") {
      if (!v.is_array() || v.empty()) fail(src, k, "expected a non-empty list of integers");
      c.seeds.clear();
      for (size_t i = 0; i < v.size(); ++i) {
        const std::string f = k + "[" + std::to_string(i) + "]";
        if (!v[i].is_number_unsigned()) fail(src, f, "expected a non-negative integer");
        const auto s = v[i].get<uint64_t>();
        for (auto seen : c.seeds)
          if (seen == s) fail(src, f, "seed " + std::to_string(s) + " listed twice");
        c.seeds.push_back(s);
      }
    } else if (k == "task") {  // every run's; checked by the evolve-config parser below
      json_field::task(v, src, k);
      task = v;
    } else if (k == "evolution") {
      if (!v.is_object()) fail(src, k, "expected an object of evolve-config fields");
      for (const char* bad : {"seed", "treatment", "threads", "format", "version"})
        if (v.contains(bad))
          fail(src, std::string("evolution.") + bad,
               "not allowed here (set per run by the experiment; threads at the top level)");
      evolution = v;
    } else if (k == "analysis") {
      parse_analysis(v, src, c.analysis);
    } else if (k == "rendering") {
      parse_rendering(v, src, c.rendering);
    } else if (k == "threads") {
      c.threads = integer(v, src, k, 0, 4096);
    } else {
      fail(src, k, "unknown field");
    }
  }
  // The evolve-config parser validates the shared settings; its errors read
  // "<src>: evolution: population: ...".
  if (law && (!evolution.contains("physics") || evolution["physics"].is_object()))
    evolution["physics"] = json::parse(
        evo::fold_law(evolution.value("physics", json::object()).dump(), *law, src, law_field));
  if (!task.is_null()) {
    if (evolution.contains("task"))
      fail(src, "evolution.task", "the task is also given at the top level (give it once)");
    evolution["task"] = task;
  }
  evolution["format"] = "plastivox-evolve-config";
  evolution["version"] = evo::kConfigVersion;
  c.evolution = evo::parse_config(evolution.dump(), src + ": evolution");
  // A study compares treatments over the bodies evolution makes (their robustness, diversity
  // and plans): AFPO and MAP-Elites make bodies, CMA-ES tunes one fixed body's genome.
  if (c.evolution.algorithm == evo::Algorithm::kCmaEs)
    fail(src, "evolution.algorithm",
         "cma-es: the experiment evolves bodies (afpo or map-elites); cma-es searches a genome "
         "of one fixed body (run it with plastivox evolve, then plastivox analyze reads its "
         "files)");
  if (c.analysis.generation > c.evolution.generations)
    fail(src, "analysis.generation",
         "generation " + std::to_string(c.analysis.generation) + " is after the last (" +
             std::to_string(c.evolution.generations) + ")");
  check_rendering_sizes(c, src);
  return c;
}

ExperimentConfig read_experiment_config(const std::string& path) {
  return parse_experiment_config(read_file_bytes(path), path);
}

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const auto& p : kEmbeddedPresets) names.emplace_back(p.name);
  return names;
}

std::string preset_text(const std::string& name) {
  std::string known;
  for (const auto& p : kEmbeddedPresets) {
    if (name == p.name) return p.text;
    known += (known.empty() ? "" : " | ") + std::string(p.name);
  }
  throw InputError("--preset: unknown preset '" + name + "' (known: " + known + ")");
}

ExperimentConfig preset_config(const std::string& name) {
  return parse_experiment_config(preset_text(name), "preset " + name);
}

}  // namespace plastivox::experiment
