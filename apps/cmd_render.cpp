// plastivox render ROBOT_OR_RESULTS --out frame.png [--time T] [--color MODE] [--size WxH] ...:
// one frame of a robot's (or a run champion's) life as a PNG.
#include <cstdio>

#include "plastivox/render/files.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {

int cmd_render(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const double time = parse_number(take_option(args, "--time", "0.2"), "--time");
  // A still: 4x multisampling costs a fraction of a second here.
  render::FrameStyle style = take_frame_style(args, 1280, 720, "msaa");
  reject_unknown_options(args);
  if (args.size() != 1)
    throw UsageError{"expected one robot or results file: plastivox render ROBOT --out frame.png"};
  if (out.empty()) throw UsageError{"--out frame.png is required"};
  check_png_out(out, "render");
  if (time < 0) throw UsageError{"--time must be >= 0"};
  render::render_frame_file(args[0], time, style, out,
                            [](const std::string& s) { log_line("render", s); });
  std::printf("wrote %s (%dx%d, t = %g s, colour %s)\n", out.c_str(), style.width, style.height,
              time, render::to_string(style.color));
  return 0;
}

}  // namespace plastivox::cli
