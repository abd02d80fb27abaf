// plastivox archive RESULTS.h5 --out DIR [--axes X,Y] [--elites N] [--size WxH]
// [--no-gallery]: a MAP-Elites run's archive as a map (DIR/archive.svg and .png, cells
// coloured by their elite's fitness), its QD score and coverage over evaluations (DIR/qd.svg
// and .png), a table (DIR/archive.csv) and a gallery of its best elites (DIR/elites.png);
// docs/evolution.md, "MAP-Elites". The drawing is the render library's
// (plastivox/render/archive_files.hpp), which the study's report uses too.
#include <cstdio>

#include "plastivox/render/archive_files.hpp"
#include "render_cli.hpp"

namespace plastivox::cli {

int cmd_archive(const Args& in) {
  Args args = in;
  const std::string out = take_option(args, "--out", "");
  const std::string axes = take_option(args, "--axes", "");
  const int elites = parse_whole(take_option(args, "--elites", "12"), "--elites");
  render::ArchiveRequest request;
  const std::string size = take_option(args, "--size", "");
  if (!size.empty()) parse_size(size, request.style.width, request.style.height);
  const bool gallery = !take_flag(args, "--no-gallery");
  reject_unknown_options(args);
  if (args.size() != 1)
    throw UsageError{"expected one results file: plastivox archive RESULTS.h5 --out DIR"};
  if (out.empty()) throw UsageError{"--out DIR is required"};
  if (elites < 1) throw UsageError{"--elites must be >= 1"};
  if (!axes.empty()) {
    const size_t comma = axes.find(',');
    if (comma == std::string::npos) throw UsageError{"--axes expects X,Y (two descriptor names)"};
    request.x_axis = axes.substr(0, comma);
    request.y_axis = axes.substr(comma + 1);
  }
  request.elites = gallery ? elites : 0;
  render::ArchiveFiles files;
  try {
    files = render::write_archive_files(args[0], out, request);
  } catch (const render::ArchiveAxisError& e) {
    throw UsageError{std::string("--axes: ") + e.what()};
  } catch (const render::GallerySizeError& e) {
    const std::string given = size.empty() ? std::string("(default)") : size;
    throw UsageError{"--size " + given + ": " + e.what()};
  }
  for (const std::string& w : files.written) std::printf("wrote %s\n", w.c_str());
  return 0;
}

}  // namespace plastivox::cli
