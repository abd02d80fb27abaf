// Reading the figure data out of stats.json. Only the fields the panels draw are read, and
// each is checked for presence and type, so a malformed or foreign file stops with one line
// that names the field ("stats.json: panels[2].groups[1].ci_low: expected a number or null").
#include <cctype>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/panels.hpp"

namespace plastivox::render {
namespace {

using Json = nlohmann::json;

constexpr const char* kFormat = "plastivox-analysis";
constexpr int kFormatVersion = 1;

// A JSON object being read, with its path for messages ("panels[1].groups[0]").
class Reader {
 public:
  Reader(const Json& j, std::string source, std::string path)
      : j_(j), source_(std::move(source)), path_(std::move(path)) {
    if (!j_.is_object()) fail(path_, "expected an object");
  }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw StatsError(source_ + ": " + (field.empty() ? std::string("(top level)") : field) + ": " +
                     what);
  }
  std::string field(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  bool has(const std::string& key) const { return j_.contains(key); }
  const Json& at(const std::string& key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) fail(field(key), "missing");
    return *it;
  }
  std::string str(const std::string& key) const {
    const Json& v = at(key);
    if (!v.is_string()) fail(field(key), "expected a string");
    return v.get<std::string>();
  }
  int count(const std::string& key) const {
    const Json& v = at(key);
    if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 1 << 30)
      fail(field(key), "expected a non-negative integer");
    return v.get<int>();
  }
  std::optional<double> number_or_null(const std::string& key) const {
    const Json& v = at(key);
    if (v.is_null()) return std::nullopt;
    if (!v.is_number()) fail(field(key), "expected a number or null");
    return v.get<double>();
  }
  const Json& array(const std::string& key) const {
    const Json& v = at(key);
    if (!v.is_array()) fail(field(key), "expected an array");
    return v;
  }
  Reader child(const Json& j, const std::string& path) const { return {j, source_, path}; }

 private:
  const Json& j_;
  std::string source_, path_;
};

PanelGroup read_group(const Reader& r) {
  PanelGroup g;
  g.treatment = r.str("treatment");
  g.n = r.count("n");
  g.mean = r.number_or_null("mean");
  g.ci_low = r.number_or_null("ci_low");
  g.ci_high = r.number_or_null("ci_high");
  if (g.ci_low.has_value() != g.ci_high.has_value())
    r.fail(r.field("ci_low"), "ci_low and ci_high must both be numbers or both null");
  if (g.ci_low && *g.ci_low > *g.ci_high) r.fail(r.field("ci_low"), "greater than ci_high");
  if (r.has("values")) {  // optional: older producers may leave the sample out
    const Json& values = r.array("values");
    for (size_t i = 0; i < values.size(); ++i) {
      if (!values[i].is_number())
        r.fail(r.field("values") + "[" + std::to_string(i) + "]", "expected a number");
      g.values.push_back(values[i].get<double>());
    }
    if (static_cast<int>(g.values.size()) != g.n)
      r.fail(r.field("values"),
             std::to_string(g.values.size()) + " values for n = " + std::to_string(g.n));
  }
  return g;
}

PanelComparison read_comparison(const Reader& r, const std::set<std::string>& treatments) {
  PanelComparison c;
  c.a = r.str("a");
  c.b = r.str("b");
  if (!treatments.count(c.a)) r.fail(r.field("a"), "'" + c.a + "' is not a group of this panel");
  if (!treatments.count(c.b)) r.fail(r.field("b"), "'" + c.b + "' is not a group of this panel");
  c.p_corrected = r.number_or_null("p_corrected");
  c.stars = r.str("stars");
  if (c.stars != "" && c.stars != "*" && c.stars != "**" && c.stars != "***")
    r.fail(r.field("stars"), "expected \"\", \"*\", \"**\" or \"***\", got \"" + c.stars + "\"");
  return c;
}

PanelStats read_panel(const Reader& r, std::set<std::string>& ids) {
  PanelStats p;
  p.id = r.str("id");
  bool ok_name = !p.id.empty() && p.id.size() <= 16;
  for (char ch : p.id) ok_name = ok_name && (std::isalnum(static_cast<unsigned char>(ch)) != 0);
  if (!ok_name) r.fail(r.field("id"), "expected 1-16 letters or digits, got \"" + p.id + "\"");
  if (!ids.insert(p.id).second) r.fail(r.field("id"), "panel \"" + p.id + "\" appears twice");
  p.metric = r.str("metric");
  p.title = r.str("title");
  p.unit = r.str("unit");
  std::set<std::string> treatments;
  const Json& groups = r.array("groups");
  for (size_t i = 0; i < groups.size(); ++i) {
    const std::string path = r.field("groups") + "[" + std::to_string(i) + "]";
    p.groups.push_back(read_group(r.child(groups[i], path)));
    if (!treatments.insert(p.groups.back().treatment).second)
      r.fail(path + ".treatment", "treatment \"" + p.groups.back().treatment + "\" appears twice");
  }
  const Json& comparisons = r.array("comparisons");
  for (size_t i = 0; i < comparisons.size(); ++i) {
    const std::string path = r.field("comparisons") + "[" + std::to_string(i) + "]";
    p.comparisons.push_back(read_comparison(r.child(comparisons[i], path), treatments));
  }
  return p;
}

std::vector<std::optional<double>> series(const Reader& r, const std::string& key) {
  const Json& a = r.array(key);
  std::vector<std::optional<double>> out;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].is_null())
      out.push_back(std::nullopt);
    else if (a[i].is_number())
      out.push_back(a[i].get<double>());
    else
      r.fail(r.field(key) + "[" + std::to_string(i) + "]", "expected a number or null");
  }
  return out;
}

EvolutionStats read_evolution(const Reader& r) {
  EvolutionStats e;
  e.unit = r.str("unit");
  const Json& runs = r.array("runs");
  for (size_t i = 0; i < runs.size(); ++i) {
    const Reader run = r.child(runs[i], r.field("runs") + "[" + std::to_string(i) + "]");
    e.runs.push_back({run.str("label"), run.str("treatment"), series(run, "best_fitness")});
  }
  const Json& bands = r.array("treatments");
  for (size_t i = 0; i < bands.size(); ++i) {
    const Reader b = r.child(bands[i], r.field("treatments") + "[" + std::to_string(i) + "]");
    EvolutionTreatmentBand t{b.str("treatment"), b.count("runs"), series(b, "mean"),
                             series(b, "ci_low"), series(b, "ci_high")};
    if (t.ci_low.size() != t.mean.size() || t.ci_high.size() != t.mean.size())
      b.fail(b.field("ci_low"), "ci_low, ci_high and mean must have the same length");
    e.treatments.push_back(std::move(t));
  }
  return e;
}

}  // namespace

BatteryHeatMap parse_battery_heat_map(const Json& block, const std::string& source,
                                      const std::string& where) {
  const Reader top(block, source, where);
  BatteryHeatMap map;
  const Json& panels = top.array("comparisons");
  for (size_t i = 0; i < panels.size(); ++i) {
    const Reader p = top.child(panels[i], top.field("comparisons") + "[" + std::to_string(i) + "]");
    map.perturbations.push_back(p.str("perturbation"));
    const Json& groups = p.array("groups");
    std::string tests;
    for (size_t k = 0; k < groups.size(); ++k) {
      const Reader g = p.child(groups[k], p.field("groups") + "[" + std::to_string(k) + "]");
      const std::string t = g.str("treatment");
      if (i == 0) map.treatments.push_back(t);
      if (k >= map.treatments.size() || map.treatments[k] != t)
        g.fail(g.field("treatment"), "treatments differ from the first perturbation's");
      map.mean.push_back(g.number_or_null("mean"));
      map.n.push_back(g.count("n"));
    }
    if (groups.size() != map.treatments.size())
      p.fail(p.field("groups"), "treatments differ from the first perturbation's");
    const Json& comparisons = p.array("comparisons");
    int unpowered = 0;
    for (size_t k = 0; k < comparisons.size(); ++k) {
      const Reader c =
          p.child(comparisons[k], p.field("comparisons") + "[" + std::to_string(k) + "]");
      const std::string stars = c.str("stars");
      if (!stars.empty())
        tests += (tests.empty() ? "" : "  ") + c.str("a") + "-" + c.str("b") + " " + stars;
      // Absent in files written before the field: those comparisons' stars already said it.
      if (c.has("powered") && !c.at("powered").is_boolean())
        c.fail(c.field("powered"), "expected true or false");
      unpowered += c.has("powered") && !c.at("powered").get<bool>() ? 1 : 0;
    }
    // As the report's table says: below 20 champions a treatment no comparison has power.
    if (unpowered > 0) tests += (tests.empty() ? "" : "  ") + std::string("no power (n < 20)");
    if (comparisons.empty()) tests = "no test (n < 2)";
    map.tests.push_back(tests);
  }
  return map;
}

StatsFigure parse_stats_figure(const Json& stats, const std::string& source) {
  const Reader top(stats, source, "");
  const std::string format = top.str("format");
  if (format != kFormat)
    top.fail("format", "\"" + format + "\" is not \"" + kFormat + "\" (not an analysis output)");
  const Json& version = top.at("format_version");
  if (!version.is_number_integer() || version.get<long long>() != kFormatVersion)
    top.fail("format_version", version.dump() + " is not supported (this build reads " +
                                   std::to_string(kFormatVersion) + ")");
  StatsFigure figure;
  figure.source = source;
  std::set<std::string> ids;
  const Json& panels = top.array("panels");
  if (panels.empty()) top.fail("panels", "empty: nothing to draw");
  for (size_t i = 0; i < panels.size(); ++i) {
    figure.panels.push_back(
        read_panel(top.child(panels[i], "panels[" + std::to_string(i) + "]"), ids));
  }
  if (stats.contains("evolution"))
    figure.evolution = read_evolution(top.child(top.at("evolution"), "evolution"));
  if (stats.contains("robustness_battery"))
    figure.battery =
        parse_battery_heat_map(stats.at("robustness_battery"), source, "robustness_battery");
  return figure;
}

StatsFigure read_stats_figure(const std::string& path) {
  std::string text;
  try {
    text = read_file_bytes(path);
  } catch (const std::exception& e) {
    throw StatsError(e.what());
  }
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw StatsError(path + ": not JSON (" + e.what() + ")");
  }
  return parse_stats_figure(j, path);
}

}  // namespace plastivox::render
