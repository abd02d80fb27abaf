// plastivox archive RESULTS.h5 --out DIR [--axes X,Y] [--elites N] [--size WxH]
// [--no-gallery]: a MAP-Elites run's archive as a map (DIR/archive.svg and .png, cells
// coloured by their elite's fitness), a table (DIR/archive.csv) and a gallery of its best
// elites (DIR/elites.png); docs/evolution.md, "MAP-Elites".
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/panels.hpp"
#include "plastivox/task.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {
namespace {

// The axes shown: the first two, or the two named by --axes X,Y.
std::pair<size_t, size_t> shown_axes(const evo::MapElitesSettings& me, const std::string& text,
                                     const std::string& file) {
  if (text.empty()) return {0, 1};
  const size_t comma = text.find(',');
  const auto index = [&](const std::string& name) {
    for (size_t k = 0; k < me.axes.size(); ++k)
      if (name == to_string(me.axes[k].what)) return k;
    std::string names;
    for (const evo::DescriptorAxis& a : me.axes) {
      if (!names.empty()) names += ", ";
      names += to_string(a.what);
    }
    throw UsageError{"--axes: '" + name + "' is not a descriptor of " + file + " (" + names + ")"};
  };
  if (comma == std::string::npos) throw UsageError{"--axes expects X,Y (two descriptor names)"};
  const size_t x = index(text.substr(0, comma)), y = index(text.substr(comma + 1));
  if (x == y) throw UsageError{"--axes: X and Y must differ"};
  return {x, y};
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

}  // namespace

int cmd_archive(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const std::string axes = take_option(args, "--axes", "");
  const int elites = parse_whole(take_option(args, "--elites", "12"), "--elites");
  render::GalleryStyle style;
  const std::string size = take_option(args, "--size", "");
  if (!size.empty()) parse_size(size, style.width, style.height);
  const bool gallery = !take_flag(args, "--no-gallery");
  reject_unknown_options(args);
  if (args.size() != 1)
    throw UsageError{"expected one results file: plastivox archive RESULTS.h5 --out DIR"};
  if (out.empty()) throw UsageError{"--out DIR is required"};
  if (elites < 1) throw UsageError{"--elites must be >= 1"};
  const std::string& file = args[0];
  const evo::ResultsFile f = evo::read_results(file);
  const evo::RunState& s = f.state;
  if (s.config.algorithm != evo::Algorithm::kMapElites)
    throw InputError(file + ": algorithm " + std::string(to_string(s.config.algorithm)) +
                     " keeps no archive (plastivox archive reads a map-elites run's)");
  const evo::MapElitesSettings& me = s.config.map_elites;
  const auto [ax, ay] = shown_axes(me, axes, file);
  const size_t shown = std::min<size_t>(static_cast<size_t>(elites), s.archive.size());
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw InputError(out + ": cannot create the output folder: " + ec.message());
  if (gallery && shown > 0) {
    try {
      render::check_gallery_request(style, shown,
                                    (std::filesystem::path(out) / "elites.png").string());
    } catch (const render::GallerySizeError& e) {
      const std::string given = size.empty() ? std::string("(default)") : size;
      throw UsageError{"--size " + given + ": " + e.what()};
    }
  }

  // The map: per shown cell the best elite over the other axes.
  render::ArchiveMap map;
  const evo::DescriptorAxis &x = me.axes[ax], &y = me.axes[ay];
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
  render::FigureOptions figure;
  figure.combined = false;
  std::vector<std::string> written = render::write_archive_map(map, out, figure);
  const std::string csv = (std::filesystem::path(out) / "archive.csv").string();
  write_file_atomic(csv, archive_csv(s));
  written.push_back(csv);

  // The gallery: the best elites (ties to the lower id), each its genome's robot.
  if (gallery && shown > 0) {
    std::vector<const evo::Individual*> best;
    for (const evo::Individual& e : s.archive) best.push_back(&e);
    std::stable_sort(best.begin(), best.end(), [](const auto* a, const auto* b) {
      return a->fitness != b->fitness ? a->fitness > b->fitness : a->id < b->id;
    });
    best.resize(shown);
    const evo::Expresser ex(s.config.expression());
    std::vector<render::GalleryEntry> entries;
    for (const evo::Individual* e : best) {
      RobotDef robot = ex.express(e->genome).robot;
      char name[64];
      std::snprintf(name, sizeof name, "elite-%llu-cell%lld",
                    static_cast<unsigned long long>(e->id), static_cast<long long>(e->cell));
      robot.name = name;
      char label[96];
      std::snprintf(label, sizeof label, "cell %lld · id %llu", static_cast<long long>(e->cell),
                    static_cast<unsigned long long>(e->id));
      render::GalleryEntry g;
      g.source = render::simulated_life_source(file, robot, s.config.physics, label);
      g.life = render::take_frame_set(g.source, render::gallery_times(s.config.physics, style));
      entries.push_back(std::move(g));
    }
    const std::string png = (std::filesystem::path(out) / "elites.png").string();
    render::render_gallery(entries, style, png);
    written.push_back(png);
  }
  for (const std::string& w : written) std::printf("wrote %s\n", w.c_str());
  return 0;
}

}  // namespace plastivox::cli
