// Off-screen drawing without a display or GPU: an OSMesa OpenGL context (Mesa's llvmpipe
// software rasterizer; OpenGL 4.5 compatibility profile on Debian 12), Dear ImGui set up on
// it for text and 2-D shapes, and deterministic PNG output.
//
// Typical use (one thread; GL contexts are per thread):
//
//   OffscreenContext ctx(1920, 1080);          // throws RenderError if OSMesa fails
//   ctx.clear(1, 1, 1);
//   {
//     ImGuiLayer ui(ctx, {{"DejaVuSans.ttf", 28}, {"DejaVuSans-Bold.ttf", 36}});
//     ui.begin_frame();
//     ImDrawList* dl = ui.draw_list();        // pixel coordinates, origin top-left
//     dl->AddText(ui.font(1), ui.font(1)->FontSize, {20, 20}, IM_COL32(0, 0, 0, 255), "A");
//     ui.end_frame_and_render();
//   }
//   write_png("out.png", ctx.read_rgba(), ctx.width(), ctx.height());
//
// Everything here is deterministic: the same calls give the same pixels and the same PNG
// bytes (llvmpipe rasterizes each screen tile on one thread, in submission order).
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/render/error.hpp"  // RenderError

struct ImDrawList;
struct ImFont;
struct ImGuiContext;

namespace plastivox::render {

// Caps llvmpipe's rasteriser threads at what a command was given (`--threads`): with 1, it
// draws on the calling thread only; with n below this machine's cores, on n threads; with 0
// or at least the cores, Mesa's default (one per core). Sets LP_NUM_THREADS, unless the user
// set it, for the contexts created after the call (Mesa reads it when it creates its first
// one): call before any drawing. The pixels do not depend on the count.
void limit_raster_threads(int threads);

// The largest image side and the largest render target the renderer accepts: width x height x
// samples (at least 1) up to 2^27, about 1 GiB of colour and depth (an 8K UHD frame with 4x
// multisampling fits; 16384x16384 does not). Larger requests are refused before anything is
// simulated or allocated (they reached 3.2 GB before OpenGL refused them).
constexpr int kMaxImageSide = 16384;
constexpr int64_t kMaxRenderTargetSamples = int64_t{1} << 27;
// Throws RenderError naming the size when a width x height image with `samples` per pixel
// (0 or 1: one) is outside these limits.
void check_render_target(int width, int height, int samples);

// An off-screen RGBA8 OpenGL context of width x height pixels with a 24-bit depth and 8-bit
// stencil buffer, current on the calling thread after construction. Not copyable; use from
// one thread. Sizes from 1x1 to 16384x16384 (1920x1080 and 3840x2160 are routine).
class OffscreenContext {
 public:
  OffscreenContext(int width, int height);  // throws RenderError naming the failing call
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  void make_current();  // binds this context to the calling thread (after using another one)

  // Clears colour (components in [0, 1]) and depth of the default framebuffer.
  void clear(float r, float g, float b, float a = 1.0f);

  // Finishes all drawing and returns the image: RGBA8, rows top-down, 4 * width * height
  // bytes (row 0 is the top of the picture).
  std::vector<uint8_t> read_rgba();

  std::string gl_version() const;   // e.g. "4.5 (Compatibility Profile) Mesa 22.3.6"
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_ = 0, height_ = 0;
};

// A TrueType font at a pixel size (the height ImGui lays glyphs out in, ~ em size). Glyphs
// loaded: Latin-1, Greek, general punctuation, super/subscripts, arrows, math operators.
struct FontSpec {
  std::string file = "DejaVuSans.ttf";  // a name resolved by find_font(), or a path
  float pixels = 16.0f;
};

// Path of a font file: `name` itself if it contains a '/', else the first existing of
// assets_dir()/fonts/name (plastivox/render/assets.hpp) and
// /usr/share/fonts/truetype/dejavu/name (Debian's fonts-dejavu-core). Throws RenderError.
std::string find_font(const std::string& name);

// Dear ImGui (1.86, OpenGL 2 backend: fixed-function GL, which OSMesa provides) drawing on
// an OffscreenContext. Owns its own ImGui context and font atlas, so several layers may
// exist at once; must be destroyed before its OffscreenContext. Writes no imgui.ini.
class ImGuiLayer {
 public:
  // fonts: at least one; font(i) is fonts[i]. Throws RenderError if a font is missing.
  explicit ImGuiLayer(OffscreenContext& ctx, const std::vector<FontSpec>& fonts = {FontSpec{}});
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // Makes the GL and ImGui contexts current and starts a frame covering the whole image.
  void begin_frame();
  // The frame's background draw list: pixel coordinates, origin at the top-left corner,
  // y down. Valid between begin_frame() and end_frame_and_render().
  ImDrawList* draw_list();
  ImFont* font(size_t i = 0) const;  // as loaded from fonts[i]; owned by the layer
  // Ends the frame and draws it over the current contents of the context (alpha-blended,
  // no depth test). Leaves GL with no program, vertex array or buffers bound.
  void end_frame_and_render();

 private:
  OffscreenContext& ctx_;
  ImGuiContext* imgui_ = nullptr;
  std::vector<ImFont*> fonts_;
  bool in_frame_ = false;
};

// Writes an RGBA8 image (rows top-down, 4 * width * height bytes) as an 8-bit RGBA PNG.
// Deterministic bytes (no time stamp or text chunks); written to a temporary and renamed
// so no half-written file is ever left under path. Throws RenderError naming path.
void write_png(const std::string& path, const std::vector<uint8_t>& rgba, int width, int height);
// Whether path's name fits the PNG bytes write_png puts there: no extension, or .png in any
// case (another, such as .jpg, would mislabel the file).
bool is_png_name(const std::string& path);
// The same PNG's bytes, in memory (`what` names the image in errors).
std::string encode_png(const std::vector<uint8_t>& rgba, int width, int height,
                       const std::string& what);

// Reads a PNG as RGBA8 rows top-down (for tests and tools). Throws RenderError naming path.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 4 * width * height
};
Image read_png(const std::string& path);

}  // namespace plastivox::render
