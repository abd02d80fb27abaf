#include "plastivox/render/gallery.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plastivox/render/offscreen.hpp"
#include "plastivox/state.hpp"

namespace plastivox::render {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

struct Item {
  LifeSource source;
  FrameSet life;
  double heading_deg = 0;
  double fitness = 0;  // voxel lengths
};

// "fitness 11.6", three significant digits: the displacement, which is the fitness under the
// walk task; under another task (jump, turn) it is not, and the label says "moved 11.6".
std::string fitness_text(const Item& it) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s %.3g",
                it.life.model->def.task == Task::kWalk ? "fitness" : "moved", it.fitness);
  return buf;
}

// UTF-8 characters in s (the label's "·" is two bytes).
int glyphs(const std::string& s) {
  int n = 0;
  for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}

// The colour scale shared by every tile: congenital stiffness over the range given, or over
// every champion's voxels (rounded outward), or over the union of the runs' physics ranges.
ColorScale gallery_scale(const std::vector<Item>& items, const GalleryStyle& style) {
  if (style.e0_lo > 0 || style.e0_hi > 0) {  // checked by check_gallery_request
    ColorScale scale;
    scale.mode = ColorMode::kCongenital;
    scale.lo = std::log10(style.e0_lo);
    scale.hi = std::log10(style.e0_hi);
    scale.title = "congenital stiffness E₀ (Pa), shared range";
    return scale;
  }
  ColorScale scale =
      make_color_scale(ColorMode::kCongenital, *items[0].life.model, {}, style.color_range);
  if (style.color_range == ColorRange::kPaper) {
    for (const Item& it : items) {
      scale.lo = std::min(scale.lo, std::log10(it.source.physics.e_min));
      scale.hi = std::max(scale.hi, std::log10(it.source.physics.e_max));
    }
    return scale;
  }
  double lo = 1e300, hi = -1e300;
  for (const Item& it : items)
    for (double e : it.life.model->e0)
      if (e > 0) {
        lo = std::min(lo, std::log10(e));
        hi = std::max(hi, std::log10(e));
      }
  return lo <= hi ? stiffness_data_scale(ColorMode::kCongenital, lo, hi) : scale;
}

// Columns so that tiles of the grid area come out about square.
int auto_columns(int n, double grid_w, double grid_h) {
  int best = 1;
  double best_err = 1e30;
  for (int c = 1; c <= n; ++c) {
    const int r = (n + c - 1) / c;
    const double aspect = (grid_w / c) / (grid_h / r);
    const double err = std::abs(std::log(aspect));
    if (err < best_err - 1e-12) {
      best_err = err;
      best = c;
    }
  }
  return best;
}

// The grid of n tiles in a gallery of this style: tiles on the left, the colour bar column
// on the right. Throws GallerySizeError when the image is too small for them.
struct Grid {
  float text_px = 0;
  int bar_column = 0, grid_w = 0, columns = 0, rows = 0, tile_w = 0, tile_h = 0;
};

Grid plan_grid(const GalleryStyle& style, int n) {
  Grid g;
  g.text_px = overlay_text_px(style.height);
  // Wide enough for the colour bar title ("congenital stiffness E0 (Pa)") beside the tiles.
  g.bar_column = style.colorbar ? static_cast<int>(std::round(g.text_px * 17)) : 0;
  g.grid_w = style.width - g.bar_column;
  const int grid_w = g.grid_w, grid_h = style.height;
  if (grid_w < 16)
    throw GallerySizeError("gallery: image too narrow (" + std::to_string(style.width) +
                           " pixels, of which the colour bar takes " +
                           std::to_string(g.bar_column) + "; try --no-colorbar or a larger size)");
  g.columns = style.columns > 0 ? std::min(style.columns, n) : auto_columns(n, grid_w, grid_h);
  g.rows = (n + g.columns - 1) / g.columns;
  g.tile_w = grid_w / g.columns;
  g.tile_h = grid_h / g.rows;
  if (g.tile_w < 8 || g.tile_h < 8)
    throw GallerySizeError("gallery: tiles would be under 8 pixels");
  try {  // the whole image and each tile's render target, before anything is simulated
    check_render_target(style.width, style.height, 1);
    check_render_target(g.tile_w, g.tile_h, style.samples);
  } catch (const RenderError& e) {
    throw GallerySizeError(std::string("gallery: ") + e.what());
  }
  return g;
}

}  // namespace

void check_gallery_size(const GalleryStyle& style, int inputs) {
  if (inputs > 0) plan_grid(style, inputs);
}

std::vector<double> gallery_times(const PhysicsDef& physics, const GalleryStyle& style) {
  const double shown = style.time < 0 ? physics.settle_time : style.time;
  return {std::min(shown, physics.duration), physics.duration};
}

void check_gallery_request(const GalleryStyle& style, size_t tiles, const std::string& out) {
  if (tiles == 0) throw RenderError("gallery: no input files");
  if (style.columns < 0) throw RenderError("gallery: --columns must be >= 0");
  if ((style.e0_lo != 0 || style.e0_hi != 0) &&
      !(style.e0_lo > 0 && style.e0_hi > style.e0_lo && std::isfinite(style.e0_hi)))
    throw RenderError("gallery: the stiffness range needs 0 < low < high (Pa)");
  check_output_path(out);
  check_gallery_size(style, static_cast<int>(tiles));
}

GalleryLayout render_gallery(const std::vector<GalleryEntry>& entries, const GalleryStyle& style,
                             const std::string& out) {
  check_gallery_request(style, entries.size(), out);

  // Heading: from the frame shown to the end of life; fitness: the displacement there.
  std::vector<Item> items;
  for (const GalleryEntry& e : entries) {
    if (e.life.frames.size() != 2) throw RenderError("gallery: a champion's frames are missing");
    Item it{e.source, e.life, 0.0, 0.0};
    const int robot_n = it.life.model->robot_n;  // the robot's voxels, not the objects'
    const Eigen::Vector3d d = center_of_mass(it.life.frames[1].pos, robot_n) -
                              center_of_mass(it.life.frames[0].pos, robot_n);
    it.heading_deg = d.head<2>().norm() > 1e-9 ? std::atan2(d.y(), d.x()) * kRadToDeg : 0.0;
    it.fitness = displacement_so_far(it.life, it.life.frames[1]);
    items.push_back(std::move(it));
  }
  const ColorScale scale = gallery_scale(items, style);

  // Layout: tiles on the left, colour bar column on the right.
  const int n = static_cast<int>(items.size());
  const Grid grid = plan_grid(style, n);
  const float text_px = grid.text_px;
  const int grid_w = grid.grid_w, tile_w = grid.tile_w, tile_h = grid.tile_h;
  GalleryLayout layout;
  layout.columns = grid.columns;
  layout.rows = grid.rows;
  const bool given = style.e0_lo > 0;
  layout.e0_lo = given ? style.e0_lo : std::pow(10.0, scale.lo);
  layout.e0_hi = given ? style.e0_hi : std::pow(10.0, scale.hi);
  // Each label on one line ("stress · seed 3 · fitness 11.6") when every one fits its tile
  // (at DejaVu Sans's average 0.6 em a character), else on two, the fitness below.
  bool one_line = true;
  for (const Item& it : items)
    one_line = one_line && 0.6 * text_px * glyphs(it.source.label + " · " + fitness_text(it)) <=
                               tile_w - text_px;
  const int label_h =
      style.labels ? static_cast<int>(std::round(text_px * (one_line ? 1.8 : 3.0))) : 0;

  // One scale for every tile: the largest robot fills ~60 % of the tile's scene height.
  double zoom_extent = 0;
  for (const Item& it : items) {
    const Camera c = follow_camera(*it.life.model, it.life.frames[0]);
    zoom_extent = std::max(zoom_extent, c.distance);
  }

  OffscreenContext ctx(style.width, style.height);
  ctx.clear(1, 1, 1);
  SceneRenderer renderer(ctx);
  for (int k = 0; k < n; ++k) {
    const Item& it = items[k];
    const Model& model = *it.life.model;
    const Frame& frame = it.life.frames[0];
    const PixelRect tile{(k % layout.columns) * tile_w, (k / layout.columns) * tile_h, tile_w,
                         tile_h};
    Scene scene;
    scene.boxes = frame_boxes(model, frame, scale);
    show_world(scene, model);
    scene.camera = follow_camera(model, frame);
    // follow_camera frames the robot's extent vertically; seen obliquely a body is up to
    // its horizontal diagonal wide (x1.3 covers it), and a tile narrower than tall sees less
    // horizontally than vertically, so back off by the aspect ratio too.
    const double aspect = static_cast<double>(tile.width) / std::max(1, tile.height - label_h);
    scene.camera.distance = zoom_extent * 1.3 * std::max(1.0, 1.0 / aspect);
    scene.camera.azimuth_deg = it.heading_deg - 60;  // travel towards the lower right
    scene.grid_spacing = model.size;
    scene.samples = style.samples;
    renderer.draw(scene, {tile.x, tile.y, tile.width, tile.height - label_h});
    layout.tiles.push_back(tile);
    layout.labels.push_back(it.source.label);
    layout.fitness.push_back(it.fitness);
    layout.heading_deg.push_back(it.heading_deg);
  }

  // Labels, tile borders and the shared colour bar.
  {
    ImGuiLayer ui(ctx, overlay_fonts(style.height));
    ui.begin_frame();
    ImDrawList* dl = ui.draw_list();
    const ImU32 ink = IM_COL32(34, 38, 46, 255);
    for (int k = 0; k < n; ++k) {
      const PixelRect& t = layout.tiles[k];
      if (style.labels) {
        ImFont* f = ui.font(0);
        const std::string fit = fitness_text(items[k]);
        const std::vector<std::string> lines =
            one_line ? std::vector<std::string>{layout.labels[k] + " · " + fit}
                     : std::vector<std::string>{layout.labels[k], fit};
        const float line_h = std::round(f->FontSize * 1.2f);
        float y = std::round(t.y + t.height - label_h + (label_h - line_h * lines.size()) / 2);
        for (const std::string& s : lines) {
          const float w = f->CalcTextSizeA(f->FontSize, 1e9f, 0, s.c_str()).x;
          dl->AddText(f, f->FontSize, ImVec2(std::round(t.x + (t.width - w) / 2), y), ink,
                      s.c_str());
          y += line_h;
        }
      }
      dl->AddRect(ImVec2(t.x + 0.5f, t.y + 0.5f),
                  ImVec2(t.x + t.width - 0.5f, t.y + t.height - 0.5f),
                  IM_COL32(200, 204, 210, 255));
    }
    if (style.colorbar) {
      const float bar_w = std::round(std::max(8.0f, text_px * 0.9f));
      const float bar_h = std::round(style.height * 0.5f);
      // The title stays in the bar's column, on as many lines as it needs.
      draw_colorbar(dl, ui.font(1), ui.font(0), scale, grid_w + text_px * 1.2f,
                    (style.height - bar_h) / 2, bar_w, bar_h, grid_w + text_px * 0.6f,
                    style.width - text_px * 0.6f);
    }
    ui.end_frame_and_render();
  }
  write_png(out, ctx.read_rgba(), style.width, style.height);
  return layout;
}

}  // namespace plastivox::render
