// report.html: a self-contained diversity report (inline CSS, an inline SVG heat map of the
// Hausdorff matrix; no scripts, no external resources apart from the caller's extra media).
//
// Index: escaping and small helpers · heat map (SVG) · sections (summary, extras, diversity,
// statistics, champions, provenance) · report_html.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "plastivox/base/markup.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis {
namespace {

using study::display;

// ---- escaping and small helpers ----

// HTML text and attribute values.
std::string esc(const std::string& s) {
  return escape_markup(s, true);
}

std::string td(const std::string& s, const char* cls = nullptr) {
  return cls ? "<td class=\"" + std::string(cls) + "\">" + s + "</td>" : "<td>" + s + "</td>";
}

std::string p_text(double p) {
  if (p < 0.001) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1e", p);
    return buf;
  }
  return display(p, 3);
}

// Viridis-like colour for t in [0, 1] (dark blue = similar, yellow = different).
std::string colour(double t) {
  static const double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 4;
  const int k = std::min(3, static_cast<int>(t));
  const double f = t - k;
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x",
                static_cast<int>(std::lround(stops[k][0] + f * (stops[k + 1][0] - stops[k][0]))),
                static_cast<int>(std::lround(stops[k][1] + f * (stops[k + 1][1] - stops[k][1]))),
                static_cast<int>(std::lround(stops[k][2] + f * (stops[k + 1][2] - stops[k][2]))));
  return buf;
}

const char* plan_symbol(BodyPlan p) {
  return symbol(p);
}

// ---- heat map (SVG) ----

std::string heat_map(const StudyResult& r) {
  const HausdorffMatrix& m = r.hausdorff;
  const int n = m.n;
  double top = 0;
  for (double d : m.distance) top = std::max(top, d);
  const int cell = std::clamp(560 / std::max(n, 1), 8, 36);
  const int label_w = 130, legend_h = 50;
  // The legend's bar, and the unit written after it (wider than the grid of a few champions).
  const int lw = std::max(120, n * cell / 2);
  const int w = label_w + std::max(n * cell + 20, lw + 100), h = label_w + n * cell + legend_h;
  std::string s;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"%d\" role=\"img\">"
                "<title>Hausdorff distance between champions (voxel lengths)</title>\n",
                w, h, w, h, std::clamp(cell - 2, 7, 12));
  s += buf;
  for (int i = 0; i < n; ++i) {
    const std::string label = esc(r.champions[i].label);
    const int c = label_w + i * cell + cell / 2;
    std::snprintf(buf, sizeof buf,
                  "<text x=\"%d\" y=\"%d\" text-anchor=\"end\" dominant-baseline=\"middle\">",
                  label_w - 4, c);
    s += buf + label + "</text>";
    std::snprintf(buf, sizeof buf,
                  "<text transform=\"translate(%d,%d) rotate(-90)\" dominant-baseline=\"middle\">",
                  c, label_w - 4);
    s += buf + label + "</text>\n";
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double d = m.at(i, j);
      std::snprintf(buf, sizeof buf,
                    "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\">",
                    label_w + j * cell, label_w + i * cell, cell, cell,
                    colour(top > 0 ? d / top : 0).c_str());
      s += buf + std::string("<title>") + esc(r.champions[i].label) + " vs " +
           esc(r.champions[j].label) + ": " + display(d, 4) + "</title></rect>";
    }
  s += "\n";
  // Lines between treatments.
  for (int i = 1; i < n; ++i) {
    if (r.champions[i].treatment == r.champions[i - 1].treatment) continue;
    const int x = label_w + i * cell;
    std::snprintf(
        buf, sizeof buf,
        "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"#fff\" stroke-width=\"2\"/>"
        "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"#fff\" stroke-width=\"2\"/>",
        x, label_w, x, label_w + n * cell, label_w, x, label_w + n * cell, x);
    s += buf;
  }
  // Legend: 0 .. the largest distance under the bar's ends, the unit after it (under the bar,
  // a long number and the unit ran into the 0).
  const int ly = label_w + n * cell + 16;
  for (int k = 0; k < 32; ++k) {
    std::snprintf(buf, sizeof buf,
                  "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"10\" fill=\"%s\"/>",
                  label_w + k * lw / 32, ly, lw / 32 + 1, colour(k / 31.0).c_str());
    s += buf;
  }
  std::snprintf(
      buf, sizeof buf,
      "<text x=\"%d\" y=\"%d\">0</text><text x=\"%d\" y=\"%d\" text-anchor=\"end\">%s</text>"
      "<text x=\"%d\" y=\"%d\" dominant-baseline=\"middle\">voxel lengths</text>",
      label_w, ly + 24, label_w + lw, ly + 24, display(top, 4).c_str(), label_w + lw + 6, ly + 5);
  s += buf;
  return s + "</svg>\n";
}

// ---- sections ----

// The warning a table of comparisons carries when some rest on fewer than kMinBootstrapN
// champions per treatment (Fig. 5's statistics and the battery's alike); "" when all have power.
std::string no_power_note(const study::PowerSummary& power, const std::string& id) {
  if (power.without_power == 0) return "";
  return "<p class=\"warn\" id=\"" + id +
         "\">These comparisons have no statistical power: " + std::to_string(power.without_power) +
         " of " + std::to_string(power.comparisons) + " rest on fewer than " +
         std::to_string(kMinBootstrapN) +
         " champions per treatment (the fewest: " + std::to_string(power.fewest) + "). Below " +
         std::to_string(kMinBootstrapN) +
         " the 95 % bootstrap interval misses the true mean far more often than 5 % of the "
         "time (about half the time at n = 2; docs/analysis.md, \"How many champions a "
         "comparison needs\"), so they carry no stars, and a difference between treatments "
         "here, in either direction, is no evidence either way.</p>\n";
}

// The robustness battery (only with one): per perturbation and treatment the mean AUC of the
// fitness kept with its bootstrap CI, cells coloured from red (all lost) through white (all
// kept) to blue (doubled), the corrected tests, and the lives that failed.
std::string battery_section(const StudyResult& r) {
  if (!r.battery || r.battery_panels.empty()) return "";
  std::string s =
      "<h2>Robustness battery</h2>\n<p>Battery <code>" + esc(r.battery->name) +
      "</code>: each champion's fitness kept (F perturbed / F unperturbed) at each severity of "
      "each perturbation, summarised by the area under its curve over the severities (1 = all "
      "fitness kept). Means per treatment with " +
      display(r.options.ci_level * 100, 4) +
      " % bootstrap intervals; tests Bonferroni-corrected as in Fig. 5. Cells are red where "
      "fitness is lost (0: all of it), white where it is kept (1) and blue where it grows (2: "
      "doubled). Lives that went unstable or sank are counted below and left out of the "
      "means, never scored as 0; a champion with no valid life at some severity has no area "
      "for that perturbation and is left out of its mean (counted in its cell).</p>\n" +
      no_power_note(study::power_summary(r.battery_panels), "battery-no-power") +
      "<table class=\"battery\"><tr><th>perturbation</th>";
  for (Treatment t : r.treatments) s += "<th>" + esc(to_string(t)) + "</th>";
  s += "<th>tests</th></tr>\n";
  // Champions of each treatment the battery measured (not left out of the study by the audit).
  std::map<Treatment, size_t> measured;
  for (const ChampionAnalysis& c : r.champions)
    if (c.artifact.empty()) ++measured[c.treatment];
  for (const PanelStats& p : r.battery_panels) {
    s += "<tr><td>" + esc(p.title) + "</td>";
    for (const GroupStats& g : p.groups) {
      const size_t out =
          measured[g.treatment] > g.values.size() ? measured[g.treatment] - g.values.size() : 0;
      const std::string left_out =
          out > 0 ? ", " + std::to_string(out) + " left out (no valid life at a severity)" : "";
      if (!g.mean) {
        s += "<td>undefined" + left_out + "</td>";
        continue;
      }
      const double t = std::clamp(0.5 + (1 - *g.mean) / 2, 0.0, 1.0);  // 0 blue .. 1 red
      char bg[64];
      std::snprintf(bg, sizeof bg, "background:rgb(%d,%d,%d)",
                    static_cast<int>(std::lround(t < 0.5 ? 80 + 350 * t : 255)),
                    static_cast<int>(std::lround(255 - 300 * std::abs(t - 0.5))),
                    static_cast<int>(std::lround(t > 0.5 ? 255 - 350 * (t - 0.5) : 255)));
      s += "<td style=\"" + std::string(bg) + "\">" + display(g.mean, 3) +
           (g.ci ? " [" + display(g.ci->lower, 3) + ", " + display(g.ci->upper, 3) + "]" : "") +
           " n=" + std::to_string(g.values.size()) + left_out + "</td>";
    }
    std::string tests;
    for (const BootstrapTestResult& c : p.comparisons) {
      const std::string stars = study::stars_shown(p, c);
      tests += (tests.empty() ? "" : "; ") + c.name_a + "-" + c.name_b +
               " p=" + p_text(c.p_corrected) + (stars.empty() ? "" : " " + stars) +
               (study::has_power(p, c)
                    ? ""
                    : " (no power: n = " + std::to_string(study::comparison_champions(p, c)) + ")");
    }
    if (p.comparisons.empty())
      tests = "no test: fewer than two treatments with two or more champions";
    s += "<td>" + esc(tests) + "</td></tr>\n";
  }
  s += "</table>\n";
  s += "<p>" + std::to_string(r.battery_lives) +
       " lives simulated: " + std::to_string(r.battery_unstable) + " unstable, " +
       std::to_string(r.battery_sank) + " sank.</p>\n";
  return s;
}

std::string summary(const StudyResult& r) {
  const auto counts = study::body_plan_counts(r);
  std::string s =
      "<h2>Champions and body plans</h2>\n<table><tr><th>treatment</th><th>champions</th>"
      "<th>Π</th><th>Γ</th><th>Υ</th><th>other</th></tr>\n";
  for (Treatment t : r.treatments) {
    const auto& k = counts.at(t);
    s += "<tr>" + td(to_string(t)) + td(std::to_string(k[0] + k[1] + k[2] + k[3]), "num");
    for (int p = 0; p < 4; ++p) s += td(std::to_string(k[p]), "num");
    s += "</tr>\n";
  }
  s += "</table>\n<p class=\"note\">Body plans by the geometric rule of docs/analysis.md "
       "(template matching on the bounding box, threshold " +
       display(BodyPlanOptions{}.threshold, 2) +
       "); the confidence of each label is in the "
       "champions table.</p>\n";
  const int seeded = study::body_plan_start_runs(r);
  if (seeded > 0)
    s += "<p class=\"note\" id=\"body-plan-start\">Generation 0 of " +
         (seeded == static_cast<int>(r.inputs.size())
              ? std::string("every run")
              : std::to_string(seeded) + " of " + std::to_string(r.inputs.size()) + " runs") +
         " held one hand-built body of each plan, Π, Γ and Υ, beside random bodies (evolution "
         "config <code>initial_population: body-plans</code>, docs/evolution.md). These counts "
         "show which of those bodies, or their descendants, outlasted the random ones; they are "
         "not plans that evolved from random bodies, as in the paper.</p>\n";
  return s;
}

std::string extras_html(const ReportExtras& extras) {
  std::string s;
  for (const ReportSection& sec : extras.sections) {
    s += "<h2>" + esc(sec.title) + "</h2>\n";
    for (const std::string& p : sec.paragraphs) s += "<p>" + esc(p) + "</p>\n";
    if (!sec.media.empty())
      s += sec.wide ? "<div class=\"media wide\">\n" : "<div class=\"media\">\n";
    for (const ReportMedia& m : sec.media) {
      s += "<figure>";
      if (m.kind == ReportMedia::Kind::kImage)
        s += "<img src=\"" + esc(m.path) + "\" alt=\"" + esc(m.caption) + "\">";
      else if (m.kind == ReportMedia::Kind::kVideo)
        s += "<video controls src=\"" + esc(m.path) + "\"></video>";
      else
        s += "<a href=\"" + esc(m.path) + "\">" + esc(m.path) + "</a>";
      if (!m.caption.empty() || !m.links.empty()) {
        s += "<figcaption>" + esc(m.caption);
        for (const auto& [label, path] : m.links)
          s += " <a href=\"" + esc(path) + "\">" + esc(label) + "</a>";
        s += "</figcaption>";
      }
      s += "</figure>\n";
    }
    if (!sec.media.empty()) s += "</div>\n";
    s += sec.raw_html;
  }
  return s;
}

std::string pair_table(const StudyResult& r, const std::vector<std::pair<int, int>>& pairs) {
  std::string s = "<table><tr><th>a</th><th>b</th><th>distance</th></tr>\n";
  for (const auto& [i, j] : pairs) {
    const ChampionAnalysis &a = r.champions[i], &b = r.champions[j];
    s += "<tr>" + td(esc(a.label) + " (" + plan_symbol(a.body_plan.plan) + ")") +
         td(esc(b.label) + " (" + plan_symbol(b.body_plan.plan) + ")") +
         td(display(r.hausdorff.at(i, j), 4), "num") + "</tr>\n";
  }
  return s + "</table>\n";
}

std::string diversity(const StudyResult& r) {
  std::string s =
      "<h2>Diversity: Hausdorff distances</h2>\n<p>Between the filled-voxel sets "
      "of every pair of champions, minimised over rotations <b>" +
      std::string(to_string(r.hausdorff.options.rotations)) + "</b> and translation <b>" +
      to_string(r.hausdorff.options.translation) +
      "</b> (voxel lengths). Hover a cell for its value.</p>\n";
  // Beside the panel: champions whose distance is the seed's, not evolution's.
  for (const std::string& note : study::shared_body_notes(r))
    s += "<p class=\"warn\" id=\"shared-body\">" + esc(note) + ".</p>\n";
  s += heat_map(r);
  s += "<div class=\"pairs\"><div><h3>Most similar pairs</h3>" +
       pair_table(r, study::extreme_pairs(r.hausdorff, 5, true)) + "</div>";
  s += "<div><h3>Least similar pairs</h3>" +
       pair_table(r, study::extreme_pairs(r.hausdorff, 5, false)) + "</div></div>\n";
  return s;
}

// "the paper found / this study found", one row per published comparison (study_paper.cpp).
std::string paper_table(const StudyResult& r) {
  std::string s =
      "<h3 id=\"paper-comparison\">The paper found / this study found</h3>\n<p>Each comparison "
      "Kriegman et al. (2018) published for the run champions (Fig. 5 and its Results; 20 "
      "champions per treatment, P Bonferroni-corrected for three comparisons) beside this "
      "study's difference of means (b − a) with its " +
      display(r.options.ci_level * 100, 4) +
      " % percentile-bootstrap interval. A direction this study cannot resolve (fewer than " +
      std::to_string(kMinBootstrapN) +
      " champions per treatment) is no contradiction, whichever way it points.</p>\n"
      "<table><tr><th>panel</th><th>the paper found</th><th>P</th><th>this study: b − a</th>"
      "<th>interval</th><th>n</th><th>p corrected</th><th>reading</th></tr>\n";
  for (const study::PaperComparison& c : study::compare_with_paper(r)) {
    const std::string title = c.title.empty() ? std::string() : " " + esc(c.title);
    s += "<tr>" + td(std::string(c.paper.panel) + title) +
         td(esc(study::direction_text(c.paper.a, c.paper.b, c.paper.direction))) +
         td(esc(c.paper.p_level));
    if (c.difference)
      s += td(display(c.difference->mean, 3) + " (" + to_string(c.paper.b) + " − " +
                  to_string(c.paper.a) + ")",
              "num") +
           td("[" + display(c.difference->lower, 3) + ", " + display(c.difference->upper, 3) + "]",
              "num") +
           td(std::to_string(c.n_a) + ", " + std::to_string(c.n_b), "num") +
           td(p_text(c.p_corrected), "num");
    else
      s += td("–") + td("–") +
           td(c.n_a > 0 ? std::to_string(c.n_a) + ", " + std::to_string(c.n_b) : "–", "num") +
           td("–");
    s += td(esc(c.verdict)) + "</tr>\n";
  }
  return s + "</table>\n";
}

std::string statistics(const StudyResult& r) {
  const StudyOptions& o = r.options;
  std::string s =
      "<h2>Statistics</h2>\n<p>Means with " + display(o.ci_level * 100, 4) +
      " % percentile bootstrap confidence intervals (" + std::to_string(o.resamples) +
      " resamples). Treatments compared by a two-sample bootstrap test of the difference in "
      "means (two-sided, pooled null, " +
      std::to_string(o.resamples) + " resamples, seed " + std::to_string(o.seed) +
      "), Bonferroni-corrected for the number "
      "of comparisons in each panel; stars after correction: * p&lt;0.05, ** p&lt;0.01, "
      "*** p&lt;0.001 (level " +
      display(o.alpha, 3) + "). Effect size: Hedges' g.</p>\n";
  s += no_power_note(study::power_summary(r), "no-power");
  s += "<table><tr><th>panel</th><th>treatment</th><th>n</th><th>mean</th><th>" +
       display(o.ci_level * 100, 4) + " % CI</th></tr>\n";
  for (const PanelStats& p : r.panels)
    for (const GroupStats& g : p.groups)
      s += "<tr>" + td(p.id + " " + esc(p.title)) + td(to_string(g.treatment)) +
           td(std::to_string(g.values.size()), "num") + td(display(g.mean, 4), "num") +
           td(g.ci ? "[" + display(g.ci->lower, 4) + ", " + display(g.ci->upper, 4) + "]" : "–",
              "num") +
           "</tr>\n";
  s += "</table>\n<table><tr><th>panel</th><th>comparison</th><th>difference</th><th>p</th>"
       "<th>p corrected</th><th></th><th>g</th><th>power</th></tr>\n";
  for (const PanelStats& p : r.panels)
    for (const BootstrapTestResult& t : p.comparisons) {
      const int n = study::comparison_champions(p, t);
      s += "<tr>" + td(p.id + " " + esc(p.title)) + td(t.name_a + " vs " + t.name_b) +
           td(display(t.difference, 4), "num") + td(p_text(t.p_value), "num") +
           td(p_text(t.p_corrected) + " (×" + std::to_string(t.comparisons) + ")", "num") +
           td(study::stars_shown(p, t), "stars") + td(display(t.effect.hedges_g, 3), "num") +
           td(study::has_power(p, t) ? "n = " + std::to_string(n)
                                     : "none (n = " + std::to_string(n) + ")") +
           "</tr>\n";
    }
  return s + "</table>\n" + paper_table(r);
}

std::string champions(const StudyResult& r) {
  std::string s =
      "<h2>Champions</h2>\n<table><tr><th>champion</th><th>gen.</th><th>fitness</th><th>R</th>"
      "<th>M_body</th><th>V_body</th><th>V_gain</th><th>plan</th><th>voxels</th>"
      "<th>status</th><th>floor</th><th>depth</th><th>vertical</th></tr>\n";
  for (const ChampionAnalysis& c : r.champions) {
    s += "<tr>" + td(esc(c.label)) + td(std::to_string(c.generation), "num") +
         td(c.evaluation == "ok" ? display(c.fitness, 4) : "–", "num") +
         td(display(c.r_mean, 3), "num") + td(display(c.m_body, 3), "num") +
         td(display(c.v_body, 3), "num") + td(display(c.v_gain, 3), "num") +
         td(std::string(plan_symbol(c.body_plan.plan)) + " " + display(c.body_plan.confidence, 2)) +
         td(std::to_string(c.voxels), "num") +
         td((c.status == "ok"
                 ? "ok"
                 : "<span title=\"" + esc(c.status_detail) + "\">" + esc(c.status) + "</span>") +
            (c.artifact.empty() ? "" : ", excluded")) +
         td(esc(c.health)) + td(display(c.floor_depth, 3), "num") +
         td(display(c.vertical_share, 2), "num") + "</tr>\n";
  }
  return s + "</table>\n";
}

// The audit, at the top: what was excluded (one sentence with the count for lives that are
// unstable or sank, one for lives the vertical rule flagged, when there are any), the
// direction fitness is measured in and whether the vertical rule applies to it, and the rule
// for sunk lives the runs evolved under.
std::string audit(const StudyResult& r) {
  std::string s, names, vertical_names;
  int excluded = 0;
  for (const ChampionAnalysis& c : r.champions) {
    if (c.vertical_exploit) {
      vertical_names += (vertical_names.empty() ? "" : "; ") + esc(c.label) + ": vertical share " +
                        display(c.vertical_share, 2);
      continue;
    }
    if (c.artifact.empty()) continue;
    ++excluded;
    names += (names.empty() ? "" : "; ") + esc(c.label) + ": " + esc(c.artifact);
  }
  const std::string of = " of " + std::to_string(r.champions.size()) +
                         (r.champions.size() == 1 ? " champion " : " champions ");
  if (excluded > 0)
    s += "<p class=\"warn\" id=\"excluded\">" + std::to_string(excluded) + of +
         (excluded == 1 ? "is excluded from the statistics and figures because its life, "
                          "simulated again, is"
                        : "are excluded from the statistics and figures because their lives, "
                          "simulated again, are") +
         " unstable or sank through the floor (" + names +
         "; <code>--keep-artifacts</code> keeps " + (excluded == 1 ? "it" : "them") + ").</p>\n";
  const VerticalAudit v = vertical_audit(r);
  if (v.flagged > 0) {
    const bool one = v.flagged == 1;
    s += "<p class=\"warn\" id=\"vertical\">" + std::to_string(v.flagged) + of +
         (one ? "owes" : "owe") + " too much of " + (one ? "its" : "their") +
         " fitness to vertical motion, rising (or falling) rather than walking, and " +
         (v.excluded > 0
              ? std::string(one ? "is" : "are") + " excluded from the statistics and figures (" +
                    vertical_names + "; <code>--keep-vertical</code> keeps " + (one ? "it" : "them")
              : std::string(one ? "is" : "are") +
                    " kept in the statistics and figures by "
                    "<code>--keep-vertical</code> (" +
                    vertical_names) +
         ").</p>\n";
  }
  char limit[256];
  std::snprintf(limit, sizeof limit,
                " This distance pays for a rise as for a stride: a champion whose vertical share "
                "(dz&sup2; / |d|&sup2;) is above %.2g, with |dz| of %.2g voxel lengths or more, "
                "is flagged",
                kVerticalShareLimit, kVerticalRiseMin);
  const std::string vertical_rule =
      v.applies ? std::string(limit) +
                      (r.options.keep_vertical ? " and kept (<code>--keep-vertical</code>)"
                                               : " and excluded") +
                      " (docs/engine.md, &ldquo;Vertical motion&rdquo;)."
                : std::string(
                      " The vertical rule (docs/engine.md) does not apply: only "
                      "walk&#39;s 3-D distance counts a rise as distance walked.");
  s += "<p>The task is <b>" + esc(r.task) + "</b>, on " + esc(r.environment) +
       " (docs/tasks.md). Fitness is the " + esc(r.fitness_direction) + ", in " +
       esc(r.fitness_unit) + "." +
       (r.controller.empty()
            ? std::string()
            : " The controller is <b>" + esc(r.controller) + "</b> (docs/control.md).") +
       " Lives that sank through the floor were " + esc(r.sinking_rule) +
       " during evolution (physics <code>sinking_invalid</code>, docs/engine.md); every "
       "champion was simulated again and graded for floor contact." +
       vertical_rule + "</p>\n";
  return s;
}

std::string provenance(const StudyResult& r) {
  std::string s = "<h2>Provenance</h2>\n<table class=\"kv\">";
  s += "<tr><th>plastivox</th><td>" + esc(r.version) + " (commit " + esc(r.commit) +
       ")</td></tr><tr><th>date</th><td>" + esc(r.date) + "</td></tr><tr><th>command</th><td>" +
       esc(r.options.command) + "</td></tr><tr><th>options</th><td><code>" +
       esc(options_json(r.options)) + "</code></td></tr><tr><th>fingerprint</th><td>" +
       esc(r.fingerprint) + "</td></tr></table>\n";
  s += "<table><tr><th>input</th><th>treatment</th><th>seed</th><th>generation</th>"
       "<th>content digest</th></tr>\n";
  for (const StudyInput& in : r.inputs)
    s += "<tr>" + td(esc(in.file)) + td(to_string(in.treatment)) +
         td(std::to_string(in.seed), "num") +
         td(std::to_string(in.generation) + " of " + std::to_string(in.generations_done), "num") +
         td("<code>" + esc(in.content_digest) + "</code>") + "</tr>\n";
  return s + "</table>\n";
}

const char* kStyle = R"(<style>
body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.6em}
table{border-collapse:collapse;margin:.6em 0}td,th{border:1px solid #ddd;padding:.25em .6em}
th{background:#f3f3f3;text-align:left}td.num{text-align:right;font-variant-numeric:tabular-nums}
td.stars{font-weight:bold;color:#a00}.note{color:#555;font-size:.9em}
.warn{background:#fff4e0;border:1px solid #e0b060;padding:.5em}
.pairs{display:flex;gap:2em;flex-wrap:wrap}
.media{display:grid;grid-template-columns:repeat(auto-fill,minmax(300px,1fr));gap:1em}
.media.wide{grid-template-columns:repeat(auto-fill,minmax(480px,1fr))}
figure{margin:0}figure img,figure video{width:100%;height:auto;border:1px solid #ddd}
figcaption{font-size:.9em;color:#555}code{font-size:.85em;word-break:break-all}
</style>
)";

}  // namespace

std::string report_html(const StudyResult& r, const ReportExtras& extras) {
  const std::string title = extras.title.empty() ? "plastivox diversity report" : extras.title;
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
                  esc(title) + "</title>\n" + kStyle + "</head><body>\n<h1>" + esc(title) +
                  "</h1>\n<p>" + std::to_string(r.champions.size()) +
                  " run champions; treatments: ";
  for (size_t i = 0; i < r.treatments.size(); ++i)
    s += (i ? ", " : "") + std::string(to_string(r.treatments[i]));
  s += ". Generated " + esc(r.date) + ".</p>\n";
  s += audit(r);
  for (const std::string& w : r.warnings) s += "<p class=\"warn\">Warning: " + esc(w) + "</p>\n";
  s += summary(r) + extras_html(extras) + diversity(r) + statistics(r) + battery_section(r) +
       champions(r) + provenance(r);
  return s + "</body></html>\n";
}

}  // namespace plastivox::analysis
