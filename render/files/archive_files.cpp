// A MAP-Elites run's archive from its results file (plastivox/render/archive_files.hpp): the
// map, the QD curve, the table and the elites' gallery, for plastivox archive and the study.
#include "plastivox/render/archive_files.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/qd_curve.hpp"
#include "plastivox/task.hpp"

namespace plastivox::render {
namespace {

namespace fs = std::filesystem;

// The index of the descriptor named `name`; ArchiveAxisError naming the run's descriptors.
size_t axis_index(const evo::MapElitesSettings& me, const std::string& name,
                  const std::string& file) {
  for (size_t k = 0; k < me.axes.size(); ++k)
    if (name == to_string(me.axes[k].what)) return k;
  std::string names;
  for (const evo::DescriptorAxis& a : me.axes) {
    if (!names.empty()) names += ", ";
    names += to_string(a.what);
  }
  throw ArchiveAxisError("'" + name + "' is not a descriptor of " + file + " (" + names + ")");
}

// The archive as CSV: a row per elite, ascending cell.
std::string archive_csv(const evo::RunState& s) {
  const evo::MapElitesSettings& me = s.config.map_elites;
  std::string out = "cell";
  for (const evo::DescriptorAxis& a : me.axes) out += std::string(",bin_") + to_string(a.what);
  for (const evo::DescriptorAxis& a : me.axes) out += std::string(",") + to_string(a.what);
  out += ",fitness,id,parent_id,born\n";
  char buf[64];
  for (const evo::Individual& e : s.archive) {
    out += std::to_string(e.cell);
    for (int b : evo::bins_of(me, e.cell)) {
      out += ',';
      out += std::to_string(b);
    }
    for (double d : e.descriptors) {
      std::snprintf(buf, sizeof buf, ",%.17g", d);
      out += buf;
    }
    std::snprintf(buf, sizeof buf, ",%.17g", e.fitness);
    out += buf;
    std::snprintf(buf, sizeof buf, ",%llu,%lld,%d\n", static_cast<unsigned long long>(e.id),
                  static_cast<long long>(e.parent_id), e.born);
    out += buf;
  }
  return out;
}

// The map on axes (ax, ay): per shown cell the best elite over the other axes.
ArchiveMap archive_map(const evo::RunState& s, size_t ax, size_t ay) {
  const evo::MapElitesSettings& me = s.config.map_elites;
  const evo::DescriptorAxis &x = me.axes[ax], &y = me.axes[ay];
  ArchiveMap map;
  map.x_name = to_string(x.what);
  map.y_name = to_string(y.what);
  map.x_lo = x.lo, map.x_hi = x.hi, map.x_bins = x.bins;
  map.y_lo = y.lo, map.y_hi = y.hi, map.y_bins = y.bins;
  map.fitness_unit = task_info(s.config.task).unit;
  map.fitness.assign(static_cast<size_t>(x.bins) * y.bins, std::nullopt);
  for (const evo::Individual& e : s.archive) {
    const std::vector<int> b = evo::bins_of(me, e.cell);
    std::optional<double>& cell = map.fitness[static_cast<size_t>(b[ay]) * x.bins + b[ax]];
    if (!cell || e.fitness > *cell) cell = e.fitness;
  }
  char title[160];
  std::snprintf(title, sizeof title, "MAP-Elites archive: %zu of %lld cells, QD score %.4g",
                s.archive.size(), static_cast<long long>(me.cells()),
                s.history.empty() ? 0.0 : s.history.back().qd_score);
  map.title = title;
  return map;
}

// The QD score and coverage after each generation, against the lives made by then.
QdCurve qd_curve(const evo::RunState& s) {
  QdCurve c;
  c.fitness_unit = task_info(s.config.task).unit;
  c.cells = s.config.map_elites.cells();
  std::vector<int64_t> made(s.history.size(), 0);
  for (const evo::BirthRecord& b : s.births)
    if (b.generation >= 0 && static_cast<size_t>(b.generation) < made.size())
      ++made[static_cast<size_t>(b.generation)];
  int64_t total = 0;
  for (size_t g = 0; g < s.history.size(); ++g) {
    c.evaluations.push_back(total += made[g]);
    c.qd_score.push_back(s.history[g].qd_score);
    c.filled.push_back(s.history[g].filled);
  }
  char title[160];
  std::snprintf(title, sizeof title, "QD score and coverage over %lld evaluations",
                static_cast<long long>(total));
  c.title = title;
  return c;
}

}  // namespace

ArchiveFiles write_archive_files(const std::string& file, const std::string& out,
                                 const ArchiveRequest& request) {
  const evo::ResultsFile f = evo::read_results(file);
  const evo::RunState& s = f.state;
  if (s.config.algorithm != evo::Algorithm::kMapElites)
    throw InputError(file + ": algorithm " + std::string(to_string(s.config.algorithm)) +
                     " keeps no archive (plastivox archive reads a map-elites run's)");
  const evo::MapElitesSettings& me = s.config.map_elites;
  const bool named = !request.x_axis.empty() || !request.y_axis.empty();
  const size_t ax = named ? axis_index(me, request.x_axis, file) : 0;
  const size_t ay = named ? axis_index(me, request.y_axis, file) : 1;
  if (ax == ay) throw ArchiveAxisError("X and Y must differ");
  const size_t shown =
      std::min<size_t>(static_cast<size_t>(std::max(request.elites, 0)), s.archive.size());
  const std::string png = (fs::path(out) / "elites.png").string();
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(out + ": cannot create the output folder: " + ec.message());
  if (shown > 0) check_gallery_request(request.style, shown, png);  // before any figure

  ArchiveFiles r;
  FigureOptions figure = request.figure;
  figure.combined = false;
  const ArchiveMap map = archive_map(s, ax, ay);
  r.x_name = map.x_name;
  r.y_name = map.y_name;
  r.written = write_archive_map(map, out, figure);
  const QdCurve curve = qd_curve(s);
  for (const std::string& w : write_qd_curve(curve, out, figure)) r.written.push_back(w);
  r.csv = (fs::path(out) / "archive.csv").string();
  write_file_atomic(r.csv, archive_csv(s));
  r.written.push_back(r.csv);
  if (figure.png) {
    r.map_png = (fs::path(out) / "archive.png").string();
    r.qd_png = (fs::path(out) / "qd.png").string();
  }
  r.cells = me.cells();
  r.filled = static_cast<int64_t>(s.archive.size());
  r.evaluations = curve.evaluations.empty() ? 0 : curve.evaluations.back();
  r.qd_score = curve.qd_score.empty() ? 0 : curve.qd_score.back();
  for (size_t k = 0; k < s.archive.size(); ++k)
    r.best_fitness = k == 0 ? s.archive[k].fitness : std::max(r.best_fitness, s.archive[k].fitness);
  if (shown == 0) return r;

  // The gallery: the best elites (ties to the lower id), each its genome's robot.
  std::vector<const evo::Individual*> best;
  for (const evo::Individual& e : s.archive) best.push_back(&e);
  std::stable_sort(best.begin(), best.end(), [](const auto* a, const auto* b) {
    return a->fitness != b->fitness ? a->fitness > b->fitness : a->id < b->id;
  });
  best.resize(shown);
  const evo::Expresser ex(s.config.expression());
  std::vector<GalleryEntry> entries;
  for (const evo::Individual* e : best) {
    RobotDef robot = ex.express(e->genome).robot;
    char name[64];
    std::snprintf(name, sizeof name, "elite-%llu-cell%lld", static_cast<unsigned long long>(e->id),
                  static_cast<long long>(e->cell));
    robot.name = name;
    char label[96];
    std::snprintf(label, sizeof label, "cell %lld · id %llu", static_cast<long long>(e->cell),
                  static_cast<unsigned long long>(e->id));
    GalleryEntry g;
    g.source = simulated_life_source(file, robot, s.config.physics, label);
    g.life = take_frame_set(g.source, gallery_times(s.config.physics, request.style));
    entries.push_back(std::move(g));
  }
  render_gallery(entries, request.style, png);
  r.gallery_png = png;
  r.elites = shown;
  r.written.push_back(png);
  return r;
}

}  // namespace plastivox::render
