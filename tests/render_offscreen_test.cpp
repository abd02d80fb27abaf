// The off-screen layer: OSMesa context sizes, top-down read-back, ImGui text and shapes,
// deterministic PNG files written atomically.
#include <imgui.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "plastivox/render/offscreen.hpp"
#include "test_support.hpp"

namespace plastivox::render {
namespace {

using plastivox::testing::ScratchDirTest;

const uint8_t* pixel(const std::vector<uint8_t>& rgba, int width, int x, int y) {
  return rgba.data() + (static_cast<size_t>(y) * width + x) * 4;
}

TEST(RenderOffscreen, ClearsFullHdAnd4kBuffers) {
  for (auto [w, h] : {std::pair{1920, 1080}, std::pair{3840, 2160}}) {
    OffscreenContext ctx(w, h);
    EXPECT_NE(ctx.gl_version().find("Mesa"), std::string::npos) << ctx.gl_version();
    ctx.clear(1.0f, 0.0f, 0.0f);
    const std::vector<uint8_t> rgba = ctx.read_rgba();
    ASSERT_EQ(rgba.size(), static_cast<size_t>(w) * h * 4);
    for (auto [x, y] : {std::pair{0, 0}, std::pair{w - 1, h - 1}, std::pair{w / 2, h / 3}}) {
      const uint8_t* p = pixel(rgba, w, x, y);
      EXPECT_EQ(p[0], 255);
      EXPECT_EQ(p[1], 0);
      EXPECT_EQ(p[2], 0);
      EXPECT_EQ(p[3], 255);
    }
  }
}

TEST(RenderOffscreen, RejectsImpossibleSizes) {
  EXPECT_THROW(OffscreenContext(0, 10), RenderError);
  EXPECT_THROW(OffscreenContext(20000, 10), RenderError);
}

// A filled rectangle in the top-left quarter, drawn with ImGui, comes back in the top rows.
TEST(RenderOffscreen, ImGuiRectangleIsReadBackTopDown) {
  const int w = 64, h = 48;
  OffscreenContext ctx(w, h);
  ctx.clear(1, 1, 1);
  ImGuiLayer ui(ctx);
  ui.begin_frame();
  ui.draw_list()->AddRectFilled(ImVec2(0, 0), ImVec2(32, 24), IM_COL32(0, 0, 255, 255));
  ui.end_frame_and_render();
  const std::vector<uint8_t> rgba = ctx.read_rgba();
  const uint8_t* in = pixel(rgba, w, 10, 5);
  EXPECT_EQ(in[0], 0);
  EXPECT_EQ(in[2], 255);
  const uint8_t* out = pixel(rgba, w, 10, 40);  // bottom-left: still white
  EXPECT_EQ(out[0], 255);
  EXPECT_EQ(out[2], 255);
}

// Text in a TrueType font darkens pixels inside its measured box and none outside it, and
// drawing it twice gives the same image.
TEST(RenderOffscreen, TrueTypeTextIsDrawnInsideItsBoxDeterministically) {
  const int w = 160, h = 60;
  auto draw = [&]() {
    OffscreenContext ctx(w, h);
    ctx.clear(1, 1, 1);
    ImGuiLayer ui(ctx, {{"DejaVuSans.ttf", 24}, {"DejaVuSans-Bold.ttf", 12}});
    ui.begin_frame();
    ImFont* font = ui.font(0);
    EXPECT_FLOAT_EQ(font->FontSize, 24);
    const ImVec2 size = font->CalcTextSizeA(font->FontSize, 1e9f, 0, "E = 1e5 Pa");
    EXPECT_GT(size.x, 60);
    EXPECT_LT(size.x, 150);
    ui.draw_list()->AddText(font, font->FontSize, ImVec2(5, 10), IM_COL32(0, 0, 0, 255),
                            "E = 1e5 Pa");
    ui.end_frame_and_render();
    int dark_inside = 0, dark_outside = 0;
    const std::vector<uint8_t> rgba = ctx.read_rgba();
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool inside = x >= 5 && x < 5 + size.x + 1 && y >= 10 && y < 10 + size.y + 1;
        if (pixel(rgba, w, x, y)[0] < 128) ++(inside ? dark_inside : dark_outside);
      }
    EXPECT_GT(dark_inside, 50);
    EXPECT_EQ(dark_outside, 0);
    return rgba;
  };
  EXPECT_EQ(draw(), draw());
}

TEST(RenderOffscreen, MissingFontIsAClearError) {
  OffscreenContext ctx(8, 8);
  try {
    ImGuiLayer ui(ctx, {{"NoSuchFont.ttf", 12}});
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("NoSuchFont.ttf"), std::string::npos) << e.what();
  }
}

class RenderPng : public ScratchDirTest {};

TEST_F(RenderPng, RoundTripsWithIdenticalBytesAndNoTemporaryLeft) {
  const int w = 7, h = 5;
  std::vector<uint8_t> rgba(w * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<uint8_t>(i * 37 % 256);
  write_png(path("a.png"), rgba, w, h);
  write_png(path("b.png"), rgba, w, h);
  EXPECT_EQ(testing::file_text(path("a.png")), testing::file_text(path("b.png")));
  int files = 0;  // a.png and b.png, no temporaries
  for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 2);
  const Image back = read_png(path("a.png"));
  EXPECT_EQ(back.width, w);
  EXPECT_EQ(back.height, h);
  EXPECT_EQ(back.rgba, rgba);
}

TEST_F(RenderPng, UnwritablePathIsAnErrorAndLeavesNothing) {
  const std::vector<uint8_t> rgba(4 * 4 * 4, 200);
  const std::string bad = path("no_such_dir/x.png");
  try {
    write_png(bad, rgba, 4, 4);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir_));
  EXPECT_THROW(write_png(path("short.png"), rgba, 5, 4), RenderError);
  EXPECT_THROW(read_png(path("missing.png")), RenderError);
}

}  // namespace
}  // namespace plastivox::render
