// plastivox figures STATS.json --out DIR [--size WxH] [--format png,svg] [--no-combined]:
// the paper's Fig. 5 panels (render/include/plastivox/render/panels.hpp) from an analysis
// output, as DIR/panel_<id>.svg/.png and the combined DIR/figure_5.svg/.png. Prints each path.
#include <cstdio>
#include <sstream>
#include <string>

#include "cli.hpp"
#include "plastivox/render/panels.hpp"
#include "render_cli.hpp"  // parse_size: one --size syntax for every command

namespace plastivox::cli {
namespace {

// "png,svg" -> which formats to write.
void parse_formats(const std::string& text, render::FigureOptions& o) {
  o.png = o.svg = false;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    if (item == "png") {
      o.png = true;
    } else if (item == "svg") {
      o.svg = true;
    } else {
      throw UsageError{"--format expects png, svg or png,svg; got '" + text + "'"};
    }
  }
  if (!o.png && !o.svg)
    throw UsageError{"--format expects png, svg or png,svg; got '" + text + "'"};
}

}  // namespace

int cmd_figures(const Args& in) {
  Args args = in;
  render::FigureOptions options;
  const std::string out = take_option(args, "--out", "");
  const std::string size = take_option(args, "--size", "");
  const std::string formats = take_option(args, "--format", "png,svg");
  options.combined = !take_flag(args, "--no-combined");
  reject_unknown_options(args);
  if (args.size() != 1)
    throw UsageError{"expected one STATS.json (the output of plastivox analyze)"};
  if (out.empty()) throw UsageError{"--out DIR is required"};
  if (!size.empty()) parse_size(size, options.width, options.height);
  parse_formats(formats, options);

  const render::StatsFigure figure = render::read_stats_figure(args[0]);
  for (const std::string& path : render::write_figures(figure, out, options)) {
    std::printf("%s\n", path.c_str());
  }
  return 0;
}

}  // namespace plastivox::cli
