// Command-line options shared by `plastivox render`, `video` and `gallery`.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "cli.hpp"
#include "plastivox/render/error.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/render_life.hpp"

namespace plastivox::cli {

inline double parse_number(const std::string& text, const std::string& option) {
  double v = 0;
  if (!read_number(text, v) || !std::isfinite(v))
    throw UsageError{option + " expects a number, got '" + text + "'"};
  return v;
}

inline int parse_whole(const std::string& text, const std::string& option) {
  const double v = parse_number(text, option);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    throw UsageError{option + " expects a whole number, got '" + text + "'"};
  return static_cast<int>(v);
}

// An --out that names a PNG: the image is encoded as PNG whatever the name says, so another
// extension (.jpg) would mislabel it. No extension, or .png in any case, is taken.
inline void check_png_out(const std::string& out, const char* command) {
  if (!render::is_png_name(out))
    throw UsageError{"--out " + out + ": " + command + " writes PNG only; name the file .png"};
}

// "WxH" -> width, height (1..16384 each).
inline void parse_size(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  if (x == std::string::npos)
    throw UsageError{"--size expects WxH (e.g. 1920x1080), got '" + text + "'"};
  width = parse_whole(text.substr(0, x), "--size");
  height = parse_whole(text.substr(x + 1), "--size");
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw UsageError{"--size " + text + " is outside 1x1 .. 16384x16384"};
}

// Anti-aliasing options: --antialias edge|msaa|none (msaa: 4 samples) or --samples N
// (1 = none, 2..8 = multisampling with N samples), either way a Scene::samples value.
inline int take_antialiasing(Args& args, const std::string& default_mode) {
  const std::string mode = take_option(args, "--antialias", default_mode);
  const std::string samples = take_option(args, "--samples", "");
  int n = render::kEdgeAntialiasing;
  if (mode == "msaa")
    n = 4;
  else if (mode == "none")
    n = 1;
  else if (mode != "edge")
    throw UsageError{"--antialias expects edge, msaa or none, got '" + mode + "'"};
  if (!samples.empty()) {
    n = parse_whole(samples, "--samples");
    if (n < 1 || n > 8) throw UsageError{"--samples must be 1..8"};
  }
  return n;
}

// --color-range data|paper (default data).
inline render::ColorRange take_color_range(Args& args) {
  try {
    return render::parse_color_range(take_option(args, "--color-range", "data"));
  } catch (const render::RenderError& e) {
    throw UsageError{std::string("--color-range: ") + e.what()};
  }
}

// Takes the frame-style options (size, colour, overlay, camera, anti-aliasing) out of args.
inline render::FrameStyle take_frame_style(Args& args, int default_w, int default_h,
                                           const std::string& default_antialias) {
  render::FrameStyle s;
  s.width = default_w;
  s.height = default_h;
  const std::string size = take_option(args, "--size", "");
  if (!size.empty()) parse_size(size, s.width, s.height);
  try {
    s.color = render::parse_color_mode(take_option(args, "--color", "congenital"));
  } catch (const render::RenderError& e) {
    throw UsageError{std::string("--color: ") + e.what()};
  }
  s.color_range = take_color_range(args);
  if (take_flag(args, "--no-overlay")) s.overlay = {false, false, false, false, false};
  if (take_flag(args, "--no-colorbar")) s.overlay.colorbar = false;
  if (take_flag(args, "--no-time")) s.overlay.time = false;
  if (take_flag(args, "--no-treatment")) s.overlay.treatment = false;
  if (take_flag(args, "--no-displacement")) s.overlay.displacement = false;
  if (take_flag(args, "--no-scalebar")) s.overlay.scalebar = false;
  const std::string camera = take_option(args, "--camera", "life");
  if (camera == "follow")
    s.camera = render::FrameStyle::CameraPath::kFollow;
  else if (camera != "life")
    throw UsageError{"--camera expects life or follow, got '" + camera + "'"};
  s.orthographic = take_flag(args, "--ortho");
  s.lit = !take_flag(args, "--flat");
  s.shadows = !take_flag(args, "--no-shadows");
  s.zoom = parse_number(take_option(args, "--zoom", "1"), "--zoom");
  if (!(s.zoom > 0)) throw UsageError{"--zoom must be > 0"};
  s.azimuth_deg = parse_number(take_option(args, "--azimuth", "-60"), "--azimuth");
  s.elevation_deg = parse_number(take_option(args, "--elevation", "25"), "--elevation");
  if (!(s.elevation_deg > -90 && s.elevation_deg <= 90))
    throw UsageError{"--elevation must be in (-90, 90] degrees"};
  s.samples = take_antialiasing(args, default_antialias);
  return s;
}

inline void log_line(const std::string& cmd, const std::string& line) {
  std::fprintf(stderr, "plastivox %s: %s\n", cmd.c_str(), line.c_str());
}

}  // namespace plastivox::cli
