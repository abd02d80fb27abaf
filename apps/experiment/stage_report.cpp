// Stage 4: report.html — the analysis report with the experiment's own sections (what was
// run, the figure panels, galleries and video) added; rewritten only if its bytes change.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>
#include "experiment_run.hpp"

#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/analysis/voxel_set.hpp"
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/viewer.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox_version.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;
using analysis::ReportMedia;
using analysis::ReportSection;

ReportSection experiment_section(const StageContext& ctx) {
  const auto& c = ctx.config;
  const auto& e = c.evolution;
  ReportSection s;
  s.title = "Experiment '" + c.name + "'";
  std::string treatments;
  for (auto t : c.treatments)
    treatments += (treatments.empty() ? "" : ", ") + std::string(to_string(t));
  std::string search = "AFPO, population " + std::to_string(e.population);
  if (e.algorithm == evo::Algorithm::kMapElites) {
    search = "MAP-Elites, " + std::to_string(e.population) + " lives a generation, archive";
    for (size_t k = 0; k < e.map_elites.axes.size(); ++k)
      search += std::string(k ? " x " : " ") + to_string(e.map_elites.axes[k].what) + " (" +
                std::to_string(e.map_elites.axes[k].bins) + " bins)";
  }
  search += ", " + std::to_string(c.lives_per_run()) + " lives a run";
  char buf[768];
  std::snprintf(buf, sizeof buf,
                "%d runs: treatments %s x %zu seeds; %s; %d generations%s; lattice "
                "%dx%dx%d of %.3g m voxels; %.2f s lives (%.2f s settling); E in [%.3g, %.3g] Pa.",
                c.runs(), treatments.c_str(), c.seeds.size(), search.c_str(), e.generations,
                e.initial_population == evo::InitialPopulation::kBodyPlans
                    ? " from hand-built Π, Γ, Υ bodies and random ones"
                    : " from random bodies",
                e.nx, e.ny, e.nz, e.voxel_size, e.physics.duration, e.physics.settle_time,
                e.physics.e_min, e.physics.e_max);
  s.paragraphs.push_back(buf);
  s.paragraphs.push_back("Started " + ctx.manifest_date + " by plastivox " + PLASTIVOX_VERSION +
                         " (commit " + build_git_commit() +
                         "). The full configuration is in "
                         "experiment.json, every session's log in experiment.log.");
  const auto link = [](const std::string& path, const std::string& caption) {
    ReportMedia m;
    m.kind = ReportMedia::Kind::kLink;
    m.path = path;
    m.caption = caption;
    return m;
  };
  s.media.push_back(link("experiment.json", "configuration and provenance"));
  s.media.push_back(link("experiment.log", "log of every session"));
  for (const auto& f : ctx.run_files) s.media.push_back(link(f, "evolution results " + f));
  return s;
}

// The body plan of every champion with its picture: a thumbnail cut out of its treatment's
// gallery (CSS background offsets from the gallery's sidecar, no extra image files).
// Clicking a thumbnail shows that champion in the 3-D viewer, when it has a life there.
std::string body_plan_table(const StageContext& ctx, const std::vector<std::string>& outputs,
                            const std::vector<render::ViewerLink>& lives) {
  const auto& r = ctx.config.rendering;
  const double thumb_w = 150;
  std::string rows;
  for (const auto& f : outputs) {
    if (!(f.starts_with("figures/gallery_") && f.ends_with(".json"))) continue;
    const std::string png = f.substr(0, f.size() - 5) + ".png";
    nlohmann::json side;
    try {
      side = nlohmann::json::parse(read_file_bytes(ctx.dir + "/" + f));
    } catch (const std::exception&) {
      continue;  // no sidecar: no thumbnails for this treatment
    }
    for (const auto& tile : side.at("tiles")) {
      const std::string file = tile.at("file").get<std::string>();
      const std::string label = fs::path(file).stem().string();
      const auto& rect = tile.at("rect");
      const double k = thumb_w / rect.at(2).get<double>();
      char style[320];
      std::snprintf(style, sizeof style,
                    "width:%.0fpx;height:%.0fpx;background:url(%s) -%.0fpx -%.0fpx/%.0fpx %.0fpx",
                    thumb_w, rect.at(3).get<double>() * k, png.c_str(),
                    rect.at(0).get<double>() * k, rect.at(1).get<double>() * k, r.gallery_width * k,
                    r.gallery_height * k);
      std::string plan = "?", confidence;
      for (const auto& c : ctx.study->champions)
        if (c.label == label) {
          plan = analysis::symbol(c.body_plan.plan);
          char buf[32];
          std::snprintf(buf, sizeof buf, "%.2f", c.body_plan.confidence);
          confidence = buf;
        }
      std::string click;
      for (size_t i = 0; i < lives.size(); ++i)
        if (lives[i].id == label)
          click = " title=\"show in the 3-D viewer\" onclick=\"plastivoxViewer.load(" +
                  std::to_string(i) + ");document.getElementById('pv-viewer').scrollIntoView()\"";
      rows += "<tr><td><div class=\"thumb\" role=\"img\" aria-label=\"" + label + "\" style=\"" +
              style + "\"" + click + "></div></td><td>" + label + "</td><td>" + plan +
              "</td><td class=\"num\">" + confidence + "</td></tr>\n";
    }
  }
  if (rows.empty()) return "";
  return "<table><tr><th>champion</th><th>run</th><th>body plan</th><th>confidence</th></tr>\n" +
         rows +
         "</table>\n<style>.thumb{border:1px solid #ddd}.thumb[onclick]{cursor:pointer}</style>\n";
}

// What the activity map shows after settling: how many voxels swing both ways to at least 0.9
// (at 8 frames a cycle a sine of amplitude 1 shows at least cos(pi/8) = 0.92 each way), how
// many never move, and the range of the voxels' RMS signals.
struct ActivitySummary {
  int full_swing = 0, still = 0;
  double rms_low = 0, rms_high = 0;
};
ActivitySummary summarise_activity(const std::vector<Frame>& frames, double settle_time) {
  ActivitySummary a;
  const size_t n = frames.empty() ? 0 : frames.front().actuation.size();
  std::vector<double> high(n, 0), low(n, 0), squares(n, 0);
  int counted = 0;
  for (const Frame& f : frames) {
    if (f.time < settle_time || f.actuation.size() != n) continue;
    ++counted;
    for (size_t i = 0; i < n; ++i) {
      high[i] = std::max(high[i], f.actuation[i]);
      low[i] = std::min(low[i], f.actuation[i]);
      squares[i] += f.actuation[i] * f.actuation[i];
    }
  }
  if (counted == 0 || n == 0) return a;
  a.rms_low = INFINITY;
  for (size_t i = 0; i < n; ++i) {
    a.full_swing += high[i] >= 0.9 && low[i] <= -0.9;
    a.still += std::max(high[i], -low[i]) < 0.01;
    const double rms = std::sqrt(squares[i] / counted);
    a.rms_low = std::min(a.rms_low, rms);
    a.rms_high = std::max(a.rms_high, rms);
  }
  return a;
}

// The best champion's controller activity over its life: its actuation signal, one row per
// voxel by one column per frame, as an inline image shown at its own size, on the actuation
// colour map. Its life is simulated again with the control channels, at 8 frames per actuation
// cycle (so that the sine is drawn, not aliased), at least 120 frames over the life.
ReportSection activity_section(const StageContext& ctx) {
  ReportSection s;
  const analysis::ChampionAnalysis* best = nullptr;
  for (const auto& c : ctx.study->champions)
    if (c.artifact.empty() && (!best || c.fitness > best->fitness)) best = &c;
  if (!best) return s;
  const PhysicsDef& physics = best->physics;
  SimOptions options;
  options.record_fps = std::max(8 * physics.act_frequency, 120 / physics.duration);
  options.record_control = true;
  const SimResult life =
      simulate(compile(best->robot, physics), options);  // its frames: not judged (the audit did)
  const std::vector<Frame>& frames = life.recording.frames;
  const int max_rows = 400, max_columns = 480;
  render::ActivityRaster raster = render::actuation_raster(frames, max_rows, max_columns);
  if (raster.width == 0) return s;
  if (raster.rows <= 200 && raster.columns <= 300)  // small: 2 x 2 pixels a cell, to be seen
    raster = render::actuation_raster(frames, max_rows, max_columns, 2);
  const std::string png = render::encode_png(raster.rgba, raster.width, raster.height,
                                             "controller activity of " + best->label);
  const ActivitySummary a = summarise_activity(frames, physics.settle_time);
  s.title = "Controller activity of the best champion";
  char buf[1400];
  std::snprintf(
      buf, sizeof buf,
      "%s (fitness %.3g): the actuation signal of each of its %d voxels (rows, lattice "
      "order%s) in %zu frames, %.3g per second, over its %.3g s life (columns, left to right%s), "
      "blue shrinking (-1), red swelling (+1), white at rest (still while it settles, %.3g s); "
      "%d x %d pixels, shown at their own size. After settling, %d of the %d voxels swing "
      "both ways to at least 0.9 and %d never move; the voxels' RMS signals range from %.2f to "
      "%.2f (a sine of amplitude 1 has 0.71). Stripes shifted from row to row are voxels in "
      "different phases: a mean over such voxels would cancel to white, %s.",
      best->label.c_str(), best->fitness, best->voxels,
      raster.voxels_per_row > 1
          ? (", RMS over groups of " + std::to_string(raster.voxels_per_row)).c_str()
          : "",
      frames.size(), options.record_fps, life.sim_time,
      raster.frames_per_column > 1
          ? (", RMS over groups of " + std::to_string(raster.frames_per_column) + " frames").c_str()
          : "",
      physics.settle_time, raster.width, raster.height, a.full_swing, best->voxels, a.still,
      a.rms_low, a.rms_high,
      raster.voxels_per_row > 1 || raster.frames_per_column > 1
          ? "so a cell that groups voxels or frames shows their RMS signal (how far they swing), "
            "coloured by the sign of their mean, which for a swing both ways says little of "
            "which way"
          : "which is why each voxel has its own row");
  s.paragraphs.push_back(buf);
  s.raw_html = "<img class=\"activity\" alt=\"controller activity of " + best->label +
               "\" width=\"" + std::to_string(raster.width) + "\" height=\"" +
               std::to_string(raster.height) + "\" src=\"data:image/png;base64," +
               render::base64(png) + "\">\n";
  return s;
}

// Each MAP-Elites run's archive (archives/<run>/, drawn by the rendering stage as plastivox
// archive draws it): a table of what every archive holds at the end beside the run's study
// champion, then per run its map, its QD score and coverage over evaluations and its elites.
ReportSection archive_section(const StageContext& ctx, const std::vector<std::string>& outputs) {
  ReportSection s;
  if (ctx.config.evolution.algorithm != evo::Algorithm::kMapElites) return s;
  s.title = "MAP-Elites archives";
  s.wide = true;
  const auto has = [&](const std::string& f) {
    return std::find(outputs.begin(), outputs.end(), f) != outputs.end();
  };
  std::string rows;
  for (const analysis::StudyInput& in : ctx.study->inputs) {
    const std::string label = ExperimentConfig::run_label(in.treatment, in.seed);
    const evo::RunState run = evo::read_results(in.file).state;
    const evo::MapElitesSettings& me = run.config.map_elites;
    double best = 0;
    for (size_t k = 0; k < run.archive.size(); ++k)
      best = k == 0 ? run.archive[k].fitness : std::max(best, run.archive[k].fitness);
    char best_text[32] = "—";
    if (!run.archive.empty()) std::snprintf(best_text, sizeof best_text, "%.3g", best);
    std::string champion = "—";
    for (const auto& c : ctx.study->champions)
      if (c.label == label) {
        char b[160];
        std::snprintf(b, sizeof b, "%.3g, %s%s", c.fitness,
                      std::string(analysis::symbol(c.body_plan.plan)).c_str(),
                      c.artifact.empty() ? "" : " (left out by the audit)");
        champion = b;
      }
    // The elites' body plans by analyze's rule: how many of each, and the best of each.
    const evo::Expresser ex(run.config.expression());
    int count[4] = {0, 0, 0, 0};
    double plan_best[4] = {0, 0, 0, 0};
    for (const evo::Individual& e : run.archive) {
      const int k = static_cast<int>(
          analysis::classify_body_plan(analysis::voxel_set(ex.express(e.genome).robot)).plan);
      plan_best[k] = count[k]++ == 0 ? e.fitness : std::max(plan_best[k], e.fitness);
    }
    std::string plans, plan_bests;
    for (int k = 0; k < 4; ++k) {
      char b[32] = "—";
      if (count[k] > 0) std::snprintf(b, sizeof b, "%.3g", plan_best[k]);
      plans += (k ? " / " : "") + std::to_string(count[k]);
      plan_bests += std::string(k ? " / " : "") + b;
    }
    const double qd = run.history.empty() ? 0 : run.history.back().qd_score;
    char row[768];
    std::snprintf(row, sizeof row,
                  "<tr><td>%s</td><td class=\"num\">%lld</td><td class=\"num\">%zu of %lld "
                  "(%.0f %%)</td><td class=\"num\">%.4g</td><td class=\"num\">%s</td><td>%s</td>"
                  "<td class=\"num\">%s</td><td class=\"num\">%s</td></tr>\n",
                  label.c_str(), static_cast<long long>(run.births.size()), run.archive.size(),
                  static_cast<long long>(me.cells()),
                  100.0 * static_cast<double>(run.archive.size()) / static_cast<double>(me.cells()),
                  qd, best_text, champion.c_str(), plans.c_str(), plan_bests.c_str());
    rows += row;
    const std::string dir = "archives/" + label + "/";
    const auto image = [&](const std::string& name, const std::string& caption,
                           const std::string& svg) {
      if (!has(dir + name)) return;
      ReportMedia m;
      m.path = dir + name;
      m.caption = label + ": " + caption;
      if (!svg.empty() && has(dir + svg)) m.links.push_back({"SVG", dir + svg});
      if (name == "archive.png" && has(dir + "archive.csv"))
        m.links.push_back({"CSV", dir + "archive.csv"});
      s.media.push_back(m);
    };
    image("archive.png", "the archive, each cell coloured by its elite's fitness", "archive.svg");
    image("qd.png", "QD score and coverage over evaluations", "qd.svg");
    image("elites.png", "its best elites after settling", "");
  }
  s.paragraphs.push_back(
      "Each run's archive at the end: lives made, cells filled (coverage), QD score (the sum of "
      "the elites' fitness above the offset), its best elite, and the run's champion in the "
      "statistics above (the best elite that counts: the archive admits no life that sank, went "
      "unstable or scored by rising; the audit replays it like any champion) with its body plan, "
      "then the elites by body plan (analyze's rule, docs/analysis.md) and the best fitness "
      "of each plan's elites. Below, per run: the map on the first two descriptors (a cell shows "
      "the best elite over "
      "any further axis; empty cells grey), the QD score and coverage after every generation "
      "against the lives made, and its best " +
      std::to_string(kArchiveElites) + " elites (plastivox archive draws the same files).");
  s.raw_html =
      "<table><tr><th>run</th><th>lives</th><th>cells filled</th><th>QD score</th>"
      "<th>best elite</th><th>champion (fitness, plan)</th><th>elites Π / Γ / Υ / other</th>"
      "<th>best Π / Γ / Υ / other</th></tr>\n" +
      rows + "</table>\n";
  return s;
}

}  // namespace

std::vector<std::string> stage_report(StageContext& ctx, const std::vector<std::string>& outputs) {
  analysis::ReportExtras extras;
  extras.title = "plastivox experiment '" + ctx.config.name + "'";
  extras.sections.push_back(experiment_section(ctx));

  ReportSection evolution, figures, galleries, videos;
  evolution.title = "Evolution: best fitness over generations";
  figures.title = "Figure 5: run champions compared";
  galleries.title =
      "Champion galleries (after settling, coloured by congenital stiffness on one scale for "
      "all treatments)";
  galleries.wide = true;
  videos.title = "Callus growth";
  videos.wide = true;
  // Every figure with its own caption and its vector version beside it ("SVG").
  const auto image = [&](const std::string& png, const std::string& caption) {
    ReportMedia m;
    m.path = png;
    m.caption = caption;
    const std::string svg = png.substr(0, png.size() - 4) + ".svg";
    if (std::find(outputs.begin(), outputs.end(), svg) != outputs.end())
      m.links.push_back({"SVG", svg});
    return m;
  };
  for (const auto& f : outputs) {
    const std::string name = fs::path(f).filename().string();
    if (f == "figures/evolution.png") {
      evolution.media.push_back(image(f, "Best fitness per generation"));
    } else if (f.starts_with("figures/panel_") && f.ends_with(".png")) {
      figures.media.push_back(image(f, "Panel " + name.substr(6, 1)));
    } else if (f == "figures/figure_5.png") {
      figures.media.push_back(image(f, "All panels"));
    } else if (f.starts_with("figures/gallery_") && f.ends_with(".png")) {
      galleries.media.push_back(image(f, name.substr(8, name.size() - 12)));
    } else if (f.starts_with("videos/") && f.ends_with(".mp4")) {
      ReportMedia v;
      v.kind = ReportMedia::Kind::kVideo;
      v.path = f;
      v.caption = name;
      videos.media.push_back(v);
    }
  }
  if (!evolution.media.empty()) {
    evolution.paragraphs.push_back(
        "Best fitness of each run (thin lines) and, per treatment, the mean over its runs "
        "(thick line) with a 95 % percentile-bootstrap confidence band; the numbers are in "
        "stats.json under \"evolution\", with each run's mean fitness and lineage count.");
    extras.sections.insert(extras.sections.begin(), evolution);  // the top of the report
  }
  if (!figures.media.empty()) {
    figures.paragraphs.push_back(
        "A fitness, B diversity (Hausdorff distance within a treatment), C robustness, "
        "D M_body, E V_body, F V_gain: treatment means with 95 % bootstrap confidence intervals "
        "and, for up to 30 values, each value as a dot (a champion; a pair of champions in B); "
        "stars mark Bonferroni-corrected bootstrap tests (* P<0.05, ** P<0.01, *** P<0.001).");
    extras.sections.push_back(figures);
  }
  if (!galleries.media.empty()) extras.sections.push_back(galleries);
  if (ReportSection archives = archive_section(ctx, outputs); !archives.title.empty())
    extras.sections.push_back(archives);
  // The lives the rendering stage wrote, in champion order (lives/<label>.js).
  std::vector<render::ViewerLink> lives;
  for (const auto& f : outputs)
    if (f.starts_with("lives/") && f.ends_with(".js"))
      lives.push_back({fs::path(f).stem().string(), f});
  ReportSection plans;
  plans.title = "Body plans of the champions";
  plans.raw_html = body_plan_table(ctx, outputs, lives);
  if (!plans.raw_html.empty()) {
    plans.paragraphs.push_back(
        "Each champion after settling (cut from its treatment's gallery) with its body plan "
        "(Π, Γ, Υ or other) and the rule's confidence (docs/analysis.md).");
    extras.sections.push_back(plans);
  }
  if (!lives.empty()) {
    ReportSection viewer;
    viewer.title = "Lives in 3-D";
    viewer.wide = true;
    viewer.paragraphs.push_back(
        "Each champion's whole life, replayed from its recording (" +
        std::to_string(static_cast<int>(render::kViewerFps)) +
        " frames per simulated second, in lives/): drag to orbit, scroll to zoom; pick a "
        "champion by its thumbnail above or its button here. Colour modes use the renderer's "
        "maps.");
    viewer.raw_html = render::viewer_fragment(lives, true);
    extras.sections.push_back(viewer);
  }
  if (ReportSection activity = activity_section(ctx); !activity.raw_html.empty())
    extras.sections.push_back(activity);
  if (!videos.media.empty()) {
    videos.paragraphs.push_back(
        "The best developing champion's whole life, coloured by its stiffness relative to its "
        "congenital stiffness (E/E0): stiffening and softening in a diverging colour map.");
    extras.sections.push_back(videos);
  }

  const std::string path = ctx.dir + "/report.html";
  const std::string html = analysis::report_html(*ctx.study, extras);
  // The report is made from the current results every time: rewritten when its bytes differ
  // (new results, or a report damaged or edited by hand), and left alone otherwise. A report
  // that cannot be read counts as differing.
  const bool existed = fs::exists(path);
  bool same = false;
  if (std::ifstream old{path, std::ios::binary})
    same = std::string(std::istreambuf_iterator<char>(old), {}) == html;
  if (!same) write_file_atomic(path, html);
  ctx.progress.log(same      ? "[report] report.html up to date"
                   : existed ? "[report] rewrote report.html (it differed from the report of "
                               "these results)"
                             : "[report] wrote report.html");
  return {"report.html"};
}

}  // namespace plastivox::experiment
