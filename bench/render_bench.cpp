// Rendering speed of `plastivox video` (docs/rendering.md, "Speed"): simulates a 1000-voxel
// irregular robot (demo_irregular(1000, 7), default physics) for the frames of a 30 fps video,
// then draws frames with several styles and reports wall and CPU time per frame. Not a unit
// test: speed is measured here, never asserted.
//
//   ./build/bench/render_bench                       # 1280x720, 40 frames per style
//   ./build/bench/render_bench --frames 156 --size 1920x1080
//   ./build/bench/render_bench --write-robot robot.json   # the robot, for `plastivox video`
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/render_life.hpp"

namespace {

using namespace plastivox;
using namespace plastivox::render;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Variant {
  const char* name;
  FrameStyle style;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 40, width = 1280, height = 720, voxels = 1000;
  std::string only, png_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "render_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--frames") {
      frames = std::atoi(next().c_str());
    } else if (a == "--voxels") {
      voxels = std::atoi(next().c_str());
    } else if (a == "--size") {
      const std::string s = next();
      if (std::sscanf(s.c_str(), "%dx%d", &width, &height) != 2) return 2;
    } else if (a == "--png") {
      png_dir = next();
    } else if (a == "--only") {
      only = next();
    } else if (a == "--write-robot") {
      write_robot_file(next(), demo_irregular(voxels, 7));
      return 0;
    } else {
      std::fprintf(stderr,
                   "usage: render_bench [--frames N] [--size WxH] [--voxels N] [--only NAME] "
                   "[--png DIR] [--write-robot PATH]\n");
      return 2;
    }
  }

  // Through a robot file, so the physics is exactly what `plastivox video robot.json` uses.
  const std::string robot_path = "/tmp/render_bench_robot_" + std::to_string(voxels) + ".json";
  write_robot_file(robot_path, demo_irregular(voxels, 7));
  const LifeSource source = load_life_source(robot_path);
  std::vector<double> times;
  for (int k = 0; k < frames && k / 30.0 < source.physics.duration; ++k) times.push_back(k / 30.0);
  double w0 = wall_seconds(), c0 = cpu_seconds();
  const FrameSet life = take_frame_set(source, times);
  std::printf("simulated %d voxels to t = %.2f s for %zu frames: %.2f s wall, %.2f s CPU\n",
              life.model->n, times.back(), times.size(), wall_seconds() - w0, cpu_seconds() - c0);
  std::vector<const Frame*> all;
  for (const Frame& f : life.frames) all.push_back(&f);

  std::vector<Variant> variants;
  FrameStyle base;
  base.width = width;
  base.height = height;
  variants.push_back({"default", base});
  FrameStyle s = base;
  s.samples = 4;
  variants.push_back({"msaa4", s});
  s = base;
  s.samples = 1;
  variants.push_back({"samples=1", s});
  s = base;
  s.shadows = false;
  variants.push_back({"no-shadows", s});
  s = base;
  s.overlay = {false, false, false, false, false};
  variants.push_back({"no-overlay", s});

  std::printf("%-12s %8s %10s %10s %8s\n", "style", "frames", "wall/frame", "CPU/frame", "fps");
  for (const Variant& v : variants) {
    if (!only.empty() && only != v.name) continue;
    const ColorScale scale = make_color_scale(v.style.color, *life.model, all);
    FrameRenderer renderer(v.style);
    // Warm-up (shader compilation); with --png, the last frame is written as DIR/<style>.png.
    const std::vector<uint8_t> first = renderer.render(life, life.frames.back(), scale, "none");
    if (!png_dir.empty())
      write_png(png_dir + "/" + v.name + ".png", first, v.style.width, v.style.height);
    w0 = wall_seconds();
    c0 = cpu_seconds();
    size_t bytes = 0;
    for (const Frame& f : life.frames) bytes += renderer.render(life, f, scale, "none").size();
    const double wall = wall_seconds() - w0, cpu = cpu_seconds() - c0;
    const double n = static_cast<double>(life.frames.size());
    std::printf("%-12s %8zu %9.1fms %9.1fms %8.2f\n", v.name, life.frames.size(), 1e3 * wall / n,
                1e3 * cpu / n, n / wall);
    if (bytes == 0) return 1;
  }
  return 0;
}
