// Encoding speed of the MP4 writer (render/include/plastivox/render/video_writer.hpp): frames
// per second at 1280x720 and 1920x1080 for H.264 (1 and 2 encoder threads) and MPEG-4 Part 2.
// Frames are synthetic but rendered-like: a smooth gradient background with a moving block,
// so motion search and flat areas both occur. Run:
//   ./build/bench/video_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "plastivox/render/video_writer.hpp"

namespace {

using plastivox::render::VideoOptions;
using plastivox::render::VideoWriter;

std::vector<uint8_t> frame(int w, int h, int i) {
  std::vector<uint8_t> px(4 * static_cast<size_t>(w) * h);
  const int side = h / 3, x0 = (i * 7) % (w - side), y0 = h / 2;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool block = x >= x0 && x < x0 + side && y >= y0 && y < y0 + side;
      uint8_t* p = &px[4 * (static_cast<size_t>(y) * w + x)];
      p[0] = static_cast<uint8_t>(block ? 230 : 60 + 120 * x / w);
      p[1] = static_cast<uint8_t>(block ? 120 : 80 + 100 * y / h);
      p[2] = static_cast<uint8_t>(block ? 40 : 150);
      p[3] = 255;
    }
  }
  return px;
}

// args: width, height, codec (0 = h264, 1 = mpeg4), encoder threads
void BM_Encode(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const VideoOptions o{.width = w,
                       .height = h,
                       .fps = 30,
                       .codec = state.range(2) == 0 ? "h264" : "mpeg4",
                       .threads = static_cast<int>(state.range(3))};
  constexpr int kFrames = 60;
  std::vector<std::vector<uint8_t>> frames;
  for (int i = 0; i < kFrames; ++i) frames.push_back(frame(w, h, i));
  const std::string out = std::filesystem::temp_directory_path().string() + "/video_bench_" +
                          std::to_string(::getpid()) + ".mp4";
  for (auto _ : state) {
    VideoWriter writer(out, o);
    for (const auto& f : frames) writer.add_frame(f.data());
    writer.finish();
  }
  std::filesystem::remove(out);
  state.counters["fps"] = benchmark::Counter(static_cast<double>(kFrames) * state.iterations(),
                                             benchmark::Counter::kIsRate);
  state.SetLabel(o.codec + " threads=" + std::to_string(o.threads));
}
BENCHMARK(BM_Encode)
    ->Args({1280, 720, 0, 1})
    ->Args({1280, 720, 0, 2})
    ->Args({1280, 720, 1, 1})
    ->Args({1920, 1080, 0, 1})
    ->Args({1920, 1080, 0, 2})
    ->Args({1920, 1080, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
