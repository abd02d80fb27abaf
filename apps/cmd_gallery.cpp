// plastivox gallery RESULTS.h5 [RESULTS.h5 ...] --out gallery.png [--size WxH] [--columns N]
// [--e0-range LO,HI] ...: the champions side by side (the paper's Figs. 2-4).
#include <cstdio>

#include "plastivox/render/files.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/scene.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {

int cmd_gallery(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  render::GalleryStyle style;
  const std::string size = take_option(args, "--size", "");
  if (!size.empty()) parse_size(size, style.width, style.height);
  style.columns = parse_whole(take_option(args, "--columns", "0"), "--columns");
  style.time = parse_number(take_option(args, "--time", "-1"), "--time");
  style.samples = take_antialiasing(args, "msaa");
  style.color_range = take_color_range(args);
  const std::string range = take_option(args, "--e0-range", "");
  if (!range.empty()) {
    const size_t comma = range.find(',');
    const auto bad = [&] {
      return UsageError{"--e0-range expects LO,HI in Pa with 0 < LO < HI (e.g. 1e6,1e10), got '" +
                        range + "'"};
    };
    if (comma == std::string::npos) throw bad();
    style.e0_lo = parse_number(range.substr(0, comma), "--e0-range");
    style.e0_hi = parse_number(range.substr(comma + 1), "--e0-range");
    if (!(style.e0_lo > 0 && style.e0_hi > style.e0_lo)) throw bad();
    if (style.color_range == render::ColorRange::kPaper)
      throw UsageError{"--e0-range and --color-range paper exclude each other"};
  }
  style.labels = !take_flag(args, "--no-labels");
  style.colorbar = !take_flag(args, "--no-colorbar");
  reject_unknown_options(args);
  if (args.empty())
    throw UsageError{
        "expected results files: plastivox gallery RUN.h5 [RUN.h5 ...] --out gallery.png"};
  if (out.empty()) throw UsageError{"--out gallery.png is required"};
  check_png_out(out, "gallery");
  if (style.columns < 0) throw UsageError{"--columns must be >= 0"};
  try {
    render::check_gallery_size(style, static_cast<int>(args.size()));
  } catch (const render::GallerySizeError& e) {
    throw UsageError{"--size " + (size.empty() ? std::string("(default)") : size) + ": " +
                     e.what()};
  }
  const render::GalleryLayout layout = render::render_gallery_file(
      args, style, out, [](const std::string& l) { log_line("gallery", l); });
  std::printf("wrote %s (%s, %d x %d grid, %dx%d; E0 colour range %.3g,%.3g Pa)\n", out.c_str(),
              count_of(static_cast<long long>(layout.tiles.size()), "champion").c_str(),
              layout.columns, layout.rows, style.width, style.height, layout.e0_lo, layout.e0_hi);
  return 0;
}

}  // namespace plastivox::cli
