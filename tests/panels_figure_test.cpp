// Fig. 5 panels: bar heights proportional to the means (SVG rect heights and PNG pixel extents),
// stars and brackets for significant comparisons only, SVG and PNG agreeing, deterministic
// bytes, one-line errors naming the field for malformed or foreign stats.json, and the
// `plastivox figures` command.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/panel_drawing.hpp"
#include "plastivox/render/panels.hpp"
#include "test_support.hpp"

namespace plastivox::render {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A group of n values spread evenly over mean +- 1.5 half_ci (so their mean is `mean`).
Json group(const std::string& t, double mean, double half_ci, int n = 20) {
  Json values = Json::array();
  for (int k = 0; k < n; ++k)
    values.push_back(n == 1 ? mean : mean + 1.5 * half_ci * (2.0 * k / (n - 1) - 1));
  return {{"treatment", t},
          {"n", n},
          {"mean", mean},
          {"ci_low", mean - half_ci},
          {"ci_high", mean + half_ci},
          {"values", values}};
}

Json comparison(const std::string& a, const std::string& b, double p, const std::string& stars) {
  return {{"a", a},           {"b", b},         {"mean_diff", 0.0},  {"p", p / 3},
          {"p_corrected", p}, {"stars", stars}, {"effect_size", 0.5}};
}

// A stats.json as the analysis writes it (the fields the figures read, and some they ignore):
// panel A has two significant comparisons of three, B none, D-F only the developing treatments.
Json sample_stats() {
  const auto panel = [](const std::string& id, const std::string& metric, const std::string& title,
                        const std::string& unit, Json groups, Json comparisons) {
    return Json{{"id", id},     {"metric", metric}, {"title", title},
                {"unit", unit}, {"groups", groups}, {"comparisons", comparisons}};
  };
  Json panels = Json::array();
  panels.push_back(panel(
      "A", "fitness", "Fitness", "voxel lengths",
      {group("none", 1.2, 0.2), group("stress", 2.4, 0.3), group("pressure", 3.0, 0.25)},
      {comparison("none", "stress", 0.004, "**"), comparison("none", "pressure", 0.0003, "***"),
       comparison("stress", "pressure", 0.2, "")}));
  panels.push_back(
      panel("B", "diversity", "Diversity", "Hausdorff distance (voxel lengths)",
            {group("none", 4.0, 0.5), group("stress", 4.5, 0.6), group("pressure", 4.2, 0.4)},
            {comparison("none", "stress", 0.6, ""), comparison("none", "pressure", 1.0, ""),
             comparison("stress", "pressure", 0.9, "")}));
  panels.push_back(
      panel("C", "robustness", "Robustness", "F_test / F_train",
            {group("none", 0.3, 0.05), group("stress", 0.55, 0.07), group("pressure", 0.5, 0.06)},
            {comparison("none", "stress", 0.03, "*")}));
  panels.push_back(panel("D", "m_body", "M_body", "mean |E+/E0 - 1|",
                         {group("stress", 0.12, 0.02), group("pressure", 0.08, 0.01)},
                         {comparison("stress", "pressure", 0.01, "*")}));
  panels.push_back(panel("E", "v_body", "V_body", "var |E+/E0 - 1|",
                         {group("stress", 0.004, 0.001), group("pressure", 0.006, 0.001)},
                         {comparison("stress", "pressure", 0.3, "")}));
  panels.push_back(panel("F", "v_gain", "V_gain", "var of normalised alpha",
                         {group("stress", 0.05, 0.01), group("pressure", 0.02, 0.005)},
                         {comparison("stress", "pressure", 0.0009, "***")}));
  return {{"format", "plastivox-analysis"},
          {"format_version", 1},
          {"provenance", {{"version", "0.1.0"}}},
          {"treatments", {"none", "stress", "pressure"}},
          {"panels", panels},
          {"champions", Json::array()}};
}

std::string parse_error(const Json& stats) {
  return testing::error_of([&] { parse_stats_figure(stats, "stats.json"); });
}

// ---------------------------------------------------------------------------------------
// Reading stats.json
// ---------------------------------------------------------------------------------------

TEST(PanelStats, ReadsEveryPanelAndField) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  ASSERT_EQ(f.panels.size(), 6u);
  EXPECT_EQ(f.panels[0].id, "A");
  EXPECT_EQ(f.panels[0].unit, "voxel lengths");
  ASSERT_EQ(f.panels[0].groups.size(), 3u);
  EXPECT_EQ(f.panels[0].groups[1].treatment, "stress");
  EXPECT_EQ(f.panels[0].groups[1].n, 20);
  EXPECT_DOUBLE_EQ(*f.panels[0].groups[1].mean, 2.4);
  EXPECT_DOUBLE_EQ(*f.panels[0].groups[1].ci_high, 2.7);
  ASSERT_EQ(f.panels[0].comparisons.size(), 3u);
  EXPECT_EQ(f.panels[0].comparisons[1].stars, "***");
  EXPECT_EQ(f.panels[3].groups.size(), 2u);
}

TEST(PanelStats, ValuesAreReadAndOptional) {
  Json s = sample_stats();
  s["panels"][0]["groups"][0].erase("values");  // an older producer's stats.json
  const StatsFigure f = parse_stats_figure(s, "stats.json");
  EXPECT_TRUE(f.panels[0].groups[0].values.empty());
  ASSERT_EQ(f.panels[0].groups[1].values.size(), 20u);
  EXPECT_DOUBLE_EQ(f.panels[0].groups[1].values[0], 2.4 - 0.45);
}

TEST(PanelStats, NullMeanAndIntervalAreAllowed) {
  Json s = sample_stats();
  s["panels"][0]["groups"][0]["mean"] = nullptr;
  s["panels"][0]["groups"][0]["ci_low"] = nullptr;
  s["panels"][0]["groups"][0]["ci_high"] = nullptr;
  const StatsFigure f = parse_stats_figure(s, "stats.json");
  EXPECT_FALSE(f.panels[0].groups[0].mean.has_value());
  EXPECT_FALSE(f.panels[0].groups[0].ci_low.has_value());
}

TEST(PanelStats, MalformedOrForeignFilesNameTheField) {
  Json s = sample_stats();
  s["panels"][1]["groups"][2].erase("mean");
  EXPECT_EQ(parse_error(s), "stats.json: panels[1].groups[2].mean: missing");

  s = sample_stats();
  s["format"] = "plastivox-results";
  EXPECT_NE(parse_error(s).find("stats.json: format: \"plastivox-results\" is not"),
            std::string::npos);

  s = sample_stats();
  s.erase("format");
  EXPECT_EQ(parse_error(s), "stats.json: format: missing");

  s = sample_stats();
  s["format_version"] = 2;
  EXPECT_NE(parse_error(s).find("stats.json: format_version: 2 is not supported"),
            std::string::npos);

  s = sample_stats();
  s["panels"][0]["groups"][0]["ci_low"] = "low";
  EXPECT_EQ(parse_error(s), "stats.json: panels[0].groups[0].ci_low: expected a number or null");

  s = sample_stats();
  s["panels"][0]["comparisons"][0]["stars"] = "****";
  EXPECT_NE(parse_error(s).find("panels[0].comparisons[0].stars: expected"), std::string::npos);

  s = sample_stats();
  s["panels"][3]["comparisons"][0]["a"] = "none";  // D has no "none" group
  EXPECT_EQ(parse_error(s),
            "stats.json: panels[3].comparisons[0].a: 'none' is not a group of this panel");

  s = sample_stats();
  s["panels"][0]["groups"][1]["values"].erase(0);
  EXPECT_EQ(parse_error(s), "stats.json: panels[0].groups[1].values: 19 values for n = 20");

  s = sample_stats();
  s["panels"][0]["groups"][1]["values"][3] = nullptr;
  EXPECT_EQ(parse_error(s), "stats.json: panels[0].groups[1].values[3]: expected a number");

  s = sample_stats();
  s["panels"][2]["id"] = "../x";  // would escape the output directory
  EXPECT_NE(parse_error(s).find("panels[2].id: expected 1-16 letters or digits"),
            std::string::npos);

  EXPECT_EQ(parse_error(Json::array()), "stats.json: (top level): expected an object");
}

class PanelFiles : public testing::ScratchDirTest {};

TEST_F(PanelFiles, UnreadableOrNonJsonFilesFailWithTheirName) {
  EXPECT_THROW(read_stats_figure(path("absent.json")), StatsError);
  write_file_atomic(path("bad.json"), "{\"format\": ");
  try {
    read_stats_figure(path("bad.json"));
    FAIL() << "expected StatsError";
  } catch (const StatsError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path("bad.json") + ": not JSON", 0), 0u) << e.what();
  }
}

// ---------------------------------------------------------------------------------------
// Layout and SVG
// ---------------------------------------------------------------------------------------

struct SvgBar {
  std::string group;
  double x, y, w, h;
};

// The value of attribute `name` in one SVG element's text, e.g. attr("<rect x=\"3\"/>", "x").
std::string attr(const std::string& element, const std::string& name) {
  const size_t at = element.find(" " + name + "=\"");
  if (at == std::string::npos) return "";
  const size_t begin = at + name.size() + 3;
  return element.substr(begin, element.find('"', begin) - begin);
}

// Every element of the SVG that starts with `open` (e.g. "<rect class=\"bar\""), up to the end
// of its element: "/>" or the closing tag.
std::vector<std::string> elements(const std::string& svg, const std::string& open,
                                  const std::string& close) {
  std::vector<std::string> out;
  for (size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1))
    out.push_back(svg.substr(at, svg.find(close, at) + close.size() - at));
  return out;
}

std::vector<SvgBar> svg_bars(const std::string& svg) {
  std::vector<SvgBar> out;
  for (const std::string& e : elements(svg, "<rect class=\"bar\"", "/>")) {
    out.push_back({attr(e, "data-group"), std::stod(attr(e, "x")), std::stod(attr(e, "y")),
                   std::stod(attr(e, "width")), std::stod(attr(e, "height"))});
  }
  return out;
}

// The contents of every <text> element made only of asterisks.
std::multiset<std::string> svg_stars(const std::string& svg) {
  std::multiset<std::string> out;
  for (const std::string& e : elements(svg, "<text ", "</text>")) {
    const size_t begin = e.find('>') + 1;
    const std::string content = e.substr(begin, e.size() - begin - 7);
    if (!content.empty() && content.find_first_not_of('*') == std::string::npos)
      out.insert(content);
  }
  return out;
}

// Checks that heights are proportional to means: height_i / mean_i is the same for every bar,
// to within `px` pixels of each height.
void expect_proportional(const std::vector<double>& heights, const std::vector<double>& means,
                         double px) {
  ASSERT_EQ(heights.size(), means.size());
  const double scale = heights.back() / means.back();
  for (size_t i = 0; i < heights.size(); ++i) {
    EXPECT_NEAR(heights[i], means[i] * scale, px) << "bar " << i;
    EXPECT_GT(heights[i], 20) << "bar " << i << " is too small to measure";
  }
}

TEST(PanelSvg, BarHeightsAreProportionalToTheMeans) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  for (const PanelStats& p : f.panels) {
    const std::vector<SvgBar> bars = svg_bars(drawing_svg(layout_panel(p, 800, 600)));
    ASSERT_EQ(bars.size(), p.groups.size()) << p.id;
    std::vector<double> heights, means;
    for (size_t i = 0; i < bars.size(); ++i) {
      EXPECT_EQ(bars[i].group, p.groups[i].treatment);
      heights.push_back(bars[i].h);
      means.push_back(*p.groups[i].mean);
    }
    SCOPED_TRACE("panel " + p.id);
    expect_proportional(heights, means, 1.0);
    // All bars stand on one baseline (y + h), left to right.
    for (size_t i = 1; i < bars.size(); ++i) {
      EXPECT_DOUBLE_EQ(bars[i].y + bars[i].h, bars[0].y + bars[0].h);
      EXPECT_GT(bars[i].x, bars[i - 1].x + bars[i - 1].w);
    }
  }
}

TEST(PanelSvg, StarsOnlyForSignificantComparisons) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  const std::map<std::string, std::multiset<std::string>> expected = {
      {"A", {"**", "***"}}, {"B", {}}, {"C", {"*"}}, {"D", {"*"}}, {"E", {}}, {"F", {"***"}}};
  for (const PanelStats& p : f.panels) {
    EXPECT_EQ(svg_stars(drawing_svg(layout_panel(p, 800, 600))), expected.at(p.id)) << p.id;
  }
}

// Bracket placement in the layout: each bracket's stars sit above the bars it joins (with their
// error bars), and A's two brackets (none-stress "**", none-pressure "***") overlap, so they are
// stacked at least a line of stars apart.
TEST(PanelLayout, BracketsClearTheBarsAndEachOther) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  const Drawing d = layout_panel(f.panels[0], 800, 600);
  std::vector<float> tops;  // per bar: the top of the bar or of its error bar
  for (const Shape& s : d.shapes) {
    const auto* r = std::get_if<RectShape>(&s);
    if (!r) continue;
    float top = r->y;
    for (const Shape& t : d.shapes)
      if (const auto* l = std::get_if<LineShape>(&t);  // the error bar: down into the bar
          l && std::abs(l->x0 - (r->x + r->w / 2)) <= 1 && std::max(l->y0, l->y1) > r->y)
        top = std::min({top, l->y0, l->y1});
    tops.push_back(top);
  }
  ASSERT_EQ(tops.size(), 3u);
  std::map<std::string, float> star_y;
  for (const Shape& s : d.shapes)
    if (const auto* t = std::get_if<TextShape>(&s); t && t->spans[0].text.find('*') == 0)
      star_y[t->spans[0].text] = t->y;
  ASSERT_EQ(star_y.size(), 2u);
  EXPECT_LT(star_y["**"], std::min(tops[0], tops[1]));
  EXPECT_LT(star_y["***"], std::min({tops[0], tops[1], tops[2]}));
  EXPECT_GE(star_y["**"] - star_y["***"], d.fonts[0].pixels);
  EXPECT_GT(star_y["***"], d.fonts[0].pixels);  // inside the picture
}

struct SvgPoint {
  std::string group;
  double cx, cy, r;
};
std::vector<SvgPoint> svg_points(const std::string& svg) {
  std::vector<SvgPoint> out;
  for (const std::string& e : elements(svg, "<circle class=\"point\"", "/>"))
    out.push_back({attr(e, "data-group"), std::stod(attr(e, "cx")), std::stod(attr(e, "cy")),
                   std::stod(attr(e, "r"))});
  return out;
}

// The y of value v on the panel's axis, read back from two bars (baseline at 0, top at mean).
double y_of_value(const SvgBar& bar, double mean, double v) {
  const double baseline = bar.y + bar.h;
  return baseline - v * bar.h / mean;
}

// n <= 30: every champion is a point over its bar, at its value's height, inside the bar's
// width, none hidden under another; an outlier beyond the CI stretches the axis to stay in view.
// n = 31: bars only.
TEST(PanelLayout, SmallSamplesShowEveryValueAsAPoint) {
  Json s = sample_stats();
  s["panels"][0]["groups"][0] = group("none", 1.2, 0.2, 7);
  s["panels"][0]["groups"][0]["values"][6] = 5.0;  // far above the CI (and the other bars)
  s["panels"][0]["groups"][0]["mean"] = 1.2;       // the sample's mean is not re-checked
  s["panels"][0]["groups"][1] = group("stress", 2.4, 0.3, 12);
  for (int k = 0; k < 12; ++k) s["panels"][0]["groups"][1]["values"][k] = 2.4;  // all tied
  s["panels"][0]["groups"][2] = group("pressure", 3.0, 0.25, 31);
  const StatsFigure f = parse_stats_figure(s, "stats.json");
  const std::string svg = drawing_svg(layout_panel(f.panels[0], 800, 600));
  const std::vector<SvgBar> bars = svg_bars(svg);
  ASSERT_EQ(bars.size(), 3u);
  const std::vector<SvgPoint> points = svg_points(svg);
  std::map<std::string, std::vector<SvgPoint>> by_group;
  for (const SvgPoint& p : points) by_group[p.group].push_back(p);
  ASSERT_EQ(by_group["none"].size(), 7u);
  ASSERT_EQ(by_group["stress"].size(), 12u);
  EXPECT_EQ(by_group.count("pressure"), 0u) << "n = 31 is drawn as a bar only";
  for (size_t b = 0; b < 2; ++b) {
    const PanelGroup& g = f.panels[0].groups[b];
    std::vector<double> drawn, expected;
    for (const SvgPoint& p : by_group[g.treatment]) {
      drawn.push_back(p.cy);
      EXPECT_GE(p.cx - p.r, bars[b].x - 0.5) << g.treatment << ": a point leaves its bar";
      EXPECT_LE(p.cx + p.r, bars[b].x + bars[b].w + 0.5) << g.treatment;
      EXPECT_GT(p.cy - p.r, 0) << "a point is cut off at the top";
    }
    // The y scale from the tallest bar (whole-pixel bar edges: within a pixel and a half).
    for (double v : g.values) expected.push_back(y_of_value(bars[2], 3.0, v));
    std::sort(drawn.begin(), drawn.end());
    std::sort(expected.begin(), expected.end());
    for (size_t i = 0; i < drawn.size(); ++i)
      EXPECT_NEAR(drawn[i], expected[i], 1.5) << g.treatment << " point " << i;
    // No point covers another's centre.
    const auto& ps = by_group[g.treatment];
    for (size_t i = 0; i < ps.size(); ++i)
      for (size_t j = i + 1; j < ps.size(); ++j)
        EXPECT_GE(std::hypot(ps[i].cx - ps[j].cx, ps[i].cy - ps[j].cy), ps[i].r)
            << g.treatment << " points " << i << " and " << j;
  }
  // The outlier is the highest thing drawn in its bar's column but stays inside the axis.
  const double outlier_y = y_of_value(bars[2], 3.0, 5.0);
  EXPECT_LT(outlier_y, bars[2].y) << "the outlier should stand above every bar";
  // The PNG draws the same points: each centre pixel has the points' fill.
  const std::vector<uint8_t> rgba = drawing_rgba(layout_panel(f.panels[0], 800, 600));
  for (const SvgPoint& p : points) {
    const uint8_t* px = &rgba[4 * (static_cast<size_t>(p.cy) * 800 + static_cast<size_t>(p.cx))];
    EXPECT_EQ(px[0], 40) << p.group << " at " << p.cx << "," << p.cy;
    EXPECT_EQ(px[1], 40);
    EXPECT_EQ(px[2], 40);
  }
}

TEST(PanelSvg, SubscriptsAndEscapes) {
  StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  const std::string svg = drawing_svg(layout_panel(f.panels[3], 800, 600));  // "M_body"
  EXPECT_NE(svg.find(">M</tspan><tspan"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">body</tspan>"), std::string::npos);
  f.panels[3].unit = "a<b & c";
  const std::string escaped = drawing_svg(layout_panel(f.panels[3], 800, 600));
  EXPECT_NE(escaped.find("a&lt;b &amp; c"), std::string::npos);
  EXPECT_EQ(escaped.find("a<b"), std::string::npos);
}

TEST(PanelLayout, MissingMeanDrawsNoBarAndNoIntervalWithoutCi) {
  Json s = sample_stats();
  s["panels"][0]["groups"][0]["mean"] = nullptr;
  s["panels"][0]["groups"][0]["ci_low"] = nullptr;
  s["panels"][0]["groups"][0]["ci_high"] = nullptr;
  s["panels"][0]["comparisons"] = Json::array();
  const StatsFigure f = parse_stats_figure(s, "stats.json");
  const std::string svg = drawing_svg(layout_panel(f.panels[0], 800, 600));
  const std::vector<SvgBar> bars = svg_bars(svg);
  ASSERT_EQ(bars.size(), 2u);
  EXPECT_EQ(bars[0].group, "stress");
  EXPECT_NE(svg.find(">no data</text>"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// PNG
// ---------------------------------------------------------------------------------------

// Vertical extent (pixels) of the run of `colour` in column x of the image.
int column_extent(const Image& img, int x, const Rgb& colour) {
  int first = -1, last = -1;
  for (int y = 0; y < img.height; ++y) {
    const uint8_t* p = &img.rgba[4 * (static_cast<size_t>(y) * img.width + x)];
    if (p[0] == colour.r && p[1] == colour.g && p[2] == colour.b) {
      if (first < 0) first = y;
      last = y;
    }
  }
  return first < 0 ? 0 : last - first + 1;
}

TEST_F(PanelFiles, PngBarExtentsAreProportionalAndMatchTheSvg) {
  Json s = sample_stats();  // bars only: no points over the measured columns
  for (Json& panel : s["panels"])
    for (Json& g : panel["groups"]) g.erase("values");
  const StatsFigure f = parse_stats_figure(s, "stats.json");
  const std::vector<std::string> written =
      write_figures(f, path("fig"), {.width = 640, .height = 480, .combined = false});
  ASSERT_EQ(written.size(), 12u);
  for (const PanelStats& p : {f.panels[0], f.panels[4]}) {
    SCOPED_TRACE("panel " + p.id);
    const Image img = read_png(path("fig/panel_" + p.id + ".png"));
    ASSERT_EQ(img.width, 640);
    ASSERT_EQ(img.height, 480);
    const std::vector<SvgBar> bars = svg_bars(read_file_bytes(path("fig/panel_" + p.id + ".svg")));
    const Drawing d = layout_panel(p, 640, 480);
    std::vector<double> heights, means;
    size_t i = 0;
    for (const Shape& s : d.shapes) {
      const auto* r = std::get_if<RectShape>(&s);
      if (!r) continue;
      // Measure a column a quarter into the bar, clear of the error bar at its centre.
      const int extent = column_extent(img, static_cast<int>(r->x + r->w / 4), r->fill);
      EXPECT_NEAR(extent, bars.at(i).h, 1.0) << "PNG and SVG disagree on bar " << i;
      heights.push_back(extent);
      means.push_back(*p.groups.at(i).mean);
      ++i;
    }
    expect_proportional(heights, means, 1.5);
  }
}

TEST_F(PanelFiles, WritesEveryPanelAndTheCombinedFigureDeterministically) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  const FigureOptions o{.width = 400, .height = 300};
  const std::vector<std::string> first = write_figures(f, path("one"), o);
  const std::vector<std::string> second = write_figures(f, path("two"), o);
  std::vector<std::string> names;
  for (const std::string& p : first) names.push_back(fs::path(p).filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{
                       "panel_A.svg", "panel_A.png", "panel_B.svg", "panel_B.png", "panel_C.svg",
                       "panel_C.png", "panel_D.svg", "panel_D.png", "panel_E.svg", "panel_E.png",
                       "panel_F.svg", "panel_F.png", "figure_5.svg", "figure_5.png"}));
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(path("one"))) files += e.is_regular_file();
  EXPECT_EQ(files, names.size());  // no temporaries left behind
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_TRUE(read_file_bytes(first[i]) == read_file_bytes(second[i])) << names[i];
  }
  const Image all = read_png(path("one/figure_5.png"));
  EXPECT_EQ(all.width, 1200);  // 3 columns
  EXPECT_EQ(all.height, 600);  // 2 rows
}

// stats.json's "evolution" as the analysis writes it: two treatments of two runs, 4 generations.
Json with_evolution() {
  Json j = sample_stats();
  Json runs = Json::array(), bands = Json::array();
  const std::vector<std::vector<double>> best = {
      {0.1, 0.2, 0.4, 0.5}, {0.2, 0.3, 0.3, 0.6}, {0.0, 0.5, 0.9, 1.2}, {0.1, 0.6, 0.8, 1.0}};
  for (int k = 0; k < 4; ++k)
    runs.push_back({{"label", (k < 2 ? "none-s" : "stress-s") + std::to_string(k + 1)},
                    {"treatment", k < 2 ? "none" : "stress"},
                    {"seed", k + 1},
                    {"best_fitness", best[k]},
                    {"mean_fitness", best[k]},
                    {"lineages", {4, 3, 3, 2}}});
  for (int t = 0; t < 2; ++t) {
    Json mean = Json::array(), lo = Json::array(), hi = Json::array();
    for (int g = 0; g < 4; ++g) {
      const double m = (best[2 * t][g] + best[2 * t + 1][g]) / 2;
      mean.push_back(m);
      lo.push_back(m - 0.05);
      hi.push_back(m + 0.05);
    }
    bands.push_back({{"treatment", t ? "stress" : "none"},
                     {"runs", 2},
                     {"mean", mean},
                     {"ci_low", lo},
                     {"ci_high", hi}});
  }
  j["evolution"] = {
      {"metric", "best fitness"}, {"unit", "voxel lengths"}, {"runs", runs}, {"treatments", bands}};
  return j;
}

TEST_F(PanelFiles, EvolutionCurvesAreDrawnWhenTheStatsHaveThem) {
  const StatsFigure f = parse_stats_figure(with_evolution(), "stats.json");
  ASSERT_TRUE(f.evolution.has_value());
  EXPECT_EQ(f.evolution->runs.size(), 4u);
  EXPECT_FALSE(parse_stats_figure(sample_stats(), "stats.json").evolution.has_value());
  const std::vector<std::string> written =
      write_figures(f, path("ev"), {.width = 400, .height = 300});
  EXPECT_NE(std::find(written.begin(), written.end(), path("ev/evolution.png")), written.end());
  const Drawing d = layout_evolution(*f.evolution, 800, 600);
  int bands = 0, lines = 0;
  std::set<std::string> texts;
  for (const Shape& sh : d.shapes) {
    if (const auto* r = std::get_if<RectShape>(&sh)) bands += r->css_class == "band";
    if (std::holds_alternative<LineShape>(sh)) ++lines;
    if (const auto* t = std::get_if<TextShape>(&sh)) texts.insert(t->spans[0].text);
  }
  EXPECT_EQ(bands, 2 * 4);                 // a step per generation and treatment
  EXPECT_GE(lines, 4 * 3 + 2 * 3);         // 3 segments per run and per mean line
  EXPECT_TRUE(texts.count("generation"));  // the axis is labelled
  EXPECT_TRUE(texts.count("Stress (2 runs)"));
  // The PNG shows the stress colour's mean line (Okabe-Ito blue) somewhere.
  const Image img = read_png(path("ev/evolution.png"));
  int blue = 0;
  for (size_t i = 0; i + 3 < img.rgba.size(); i += 4)
    blue +=
        img.rgba[i] < 40 && img.rgba[i + 1] > 90 && img.rgba[i + 1] < 140 && img.rgba[i + 2] > 150;
  EXPECT_GT(blue, 50);
  Json bad = with_evolution();
  bad["evolution"]["treatments"][1]["ci_low"] = Json::array({0.1});
  EXPECT_NE(testing::error_of([&] {
              parse_stats_figure(bad, "stats.json");
            }).find("stats.json: evolution.treatments[1].ci_low"),
            std::string::npos);
}

TEST_F(PanelFiles, BadSizeWritesNothing) {
  const StatsFigure f = parse_stats_figure(sample_stats(), "stats.json");
  EXPECT_THROW(write_figures(f, path("x"), {.width = 50, .height = 300}), RenderError);
  EXPECT_FALSE(fs::exists(path("x")));
  // Panels of 8192 x 8192 are allowed, but their combined figure (3 x 2 panels) is not: refused
  // before any panel is drawn (it used to draw them all first, 35 s and 1.5 GB), saying how to
  // get the panels alone.
  const std::string e = testing::error_of(
      [&] { write_figures(f, path("big"), {.width = 8192, .height = 8192, .combined = true}); });
  EXPECT_NE(e.find("makes the combined figure 24576x16384"), std::string::npos) << e;
  EXPECT_NE(e.find("--no-combined"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(path("big")));
}

// ---------------------------------------------------------------------------------------
// plastivox figures
// ---------------------------------------------------------------------------------------

TEST_F(PanelFiles, CommandWritesTheChosenFormats) {
  write_file_atomic(path("stats.json"), sample_stats().dump());
  const testing::Output r =
      testing::shell(std::string(PLASTIVOX_CLI) + " figures " + path("stats.json") + " --out " +
                     path("out") + " --size 400x300 --format svg 2>&1");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find(path("out/panel_F.svg")), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(path("out/figure_5.svg")), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(".png"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(path("out/panel_A.svg")));
  EXPECT_FALSE(fs::exists(path("out/panel_A.png")));
}

TEST_F(PanelFiles, CommandErrorsAreOneLine) {
  Json foreign = sample_stats();
  foreign["format"] = "something-else";
  write_file_atomic(path("foreign.json"), foreign.dump());
  const std::string cli = std::string(PLASTIVOX_CLI) + " figures ";
  testing::Output r = testing::shell(cli + path("foreign.json") + " --out " + path("o") + " 2>&1");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out, "plastivox figures: error: " + path("foreign.json") +
                       ": format: \"something-else\" is not \"plastivox-analysis\" (not an "
                       "analysis output)\n");
  EXPECT_FALSE(fs::exists(path("o")));

  r = testing::shell(cli + path("foreign.json") + " --out " + path("o") + " --size 800by600 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--size expects WxH"), std::string::npos) << r.out;
  r = testing::shell(cli + path("foreign.json") + " --out " + path("o") + " --format pdf 2>&1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--format expects png, svg or png,svg"), std::string::npos) << r.out;
}

// ---------------------------------------------------------------------------------------
// The robustness battery's heat map
// ---------------------------------------------------------------------------------------

// stats.json's "robustness_battery" as the analysis writes it: two perturbations, two
// treatments; gravity's none-stress comparison significant.
Json with_battery() {
  Json stats = sample_stats();
  const auto perturbation = [](const std::string& name, double a, double b,
                               const std::string& stars) {
    return Json{{"perturbation", name},
                {"groups", {group("none", a, 0.05, 3), group("stress", b, 0.05, 3)}},
                {"comparisons", {comparison("none", "stress", 0.01, stars)}}};
  };
  stats["robustness_battery"] = {
      {"comparisons",
       {perturbation("paper", 0.4, 0.9, ""), perturbation("gravity", 1.0, 1.6, "*")}}};
  return stats;
}

TEST_F(PanelFiles, BatteryHeatMapIsDrawnWhenTheStatsHaveABattery) {
  const StatsFigure f = parse_stats_figure(with_battery(), "stats.json");
  ASSERT_TRUE(f.battery);
  EXPECT_EQ(f.battery->perturbations, (std::vector<std::string>{"paper", "gravity"}));
  EXPECT_EQ(f.battery->treatments, (std::vector<std::string>{"none", "stress"}));
  EXPECT_EQ(f.battery->tests, (std::vector<std::string>{"", "none-stress *"}));
  const std::vector<std::string> written =
      write_figures(f, path("fig"), FigureOptions{.width = 400, .height = 300});
  EXPECT_EQ(fs::path(written.back()).filename(), "robustness_heatmap.png");
  const std::string svg = read_file_bytes(path("fig/robustness_heatmap.svg"));
  EXPECT_NE(svg.find("0.40 (n=3)"), std::string::npos);
  EXPECT_NE(svg.find("none-stress *"), std::string::npos);
  // The cells' colours follow the means: 1.0 (all kept) is white-ish, 0.4 is red.
  const Drawing d = layout_battery_heat_map(*f.battery, 400, 300);
  std::vector<Rgb> cells;
  for (const Shape& s : d.shapes)
    if (const auto* r = std::get_if<RectShape>(&s); r && r->css_class == "cell")
      cells.push_back(r->fill);
  ASSERT_EQ(cells.size(), 4u);
  EXPECT_GT(cells[0].r, cells[0].b + 40);                          // paper/none 0.4: red
  EXPECT_GT(std::min({cells[2].r, cells[2].g, cells[2].b}), 220);  // gravity/none 1.0: white
  EXPECT_GT(cells[3].b, cells[3].r + 40);                          // gravity/stress 1.6: blue
  // A malformed block names its field.
  Json bad = with_battery();
  bad["robustness_battery"]["comparisons"][1]["groups"][0].erase("mean");
  EXPECT_NE(parse_error(bad).find(
                "stats.json: robustness_battery.comparisons[1].groups[0].mean: missing"),
            std::string::npos)
      << parse_error(bad);
  // A comparison without power (fewer than 20 champions a treatment) says so in its row, as
  // the report's battery table does; one of another type is refused naming the field.
  Json weak = with_battery();
  weak["robustness_battery"]["comparisons"][0]["comparisons"][0]["powered"] = false;
  EXPECT_EQ(parse_stats_figure(weak, "stats.json").battery->tests,
            (std::vector<std::string>{"no power (n < 20)", "none-stress *"}));
  Json none = with_battery();
  none["robustness_battery"]["comparisons"][1]["comparisons"] = Json::array();
  EXPECT_EQ(parse_stats_figure(none, "stats.json").battery->tests[1], "no test (n < 2)");
  weak["robustness_battery"]["comparisons"][0]["comparisons"][0]["powered"] = "no";
  EXPECT_NE(parse_error(weak).find("robustness_battery.comparisons[0].comparisons[0].powered: "
                                   "expected true or false"),
            std::string::npos)
      << parse_error(weak);
}

}  // namespace
}  // namespace plastivox::render
