// OSMesa context and Dear ImGui layer (see offscreen.hpp).
#include "plastivox/render/offscreen.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <backends/imgui_impl_opengl2.h>
#include <imgui.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "fp_guard.hpp"
#include "plastivox/render/assets.hpp"

namespace plastivox::render {

void limit_raster_threads(int threads) {
  const unsigned cores = std::thread::hardware_concurrency();
  if (threads <= 0 || (cores > 0 && static_cast<unsigned>(threads) >= cores)) return;
  // 0: no rasteriser threads, llvmpipe draws on the thread that calls GL.
  setenv("LP_NUM_THREADS", std::to_string(threads == 1 ? 0 : threads).c_str(), /*overwrite=*/0);
}

// ---------------------------------------------------------------------------------------
// OffscreenContext
// ---------------------------------------------------------------------------------------

struct OffscreenContext::Impl {
  OSMesaContext context = nullptr;
  std::vector<uint8_t> buffer;  // OSMesa's colour buffer, rows bottom-up (GL convention)
};

void check_render_target(int width, int height, int samples) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throw RenderError("image size " + size + " is outside 1x1 .. 16384x16384");
  const int64_t total = int64_t{width} * height * std::max(samples, 1);
  if (total > kMaxRenderTargetSamples)
    throw RenderError("image size " + size + " with " + std::to_string(std::max(samples, 1)) +
                      " sample(s) a pixel needs " + std::to_string(total) +
                      " samples of render target, more than the limit of " +
                      std::to_string(kMaxRenderTargetSamples) +
                      " (about 1 GiB): use a smaller size" +
                      (samples > 1 ? ", or --antialias edge" : ""));
}

OffscreenContext::OffscreenContext(int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  check_render_target(width, height, 1);
  FpTrapsMasked masked;  // llvmpipe's worker threads start here and inherit this state
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         8,
                         OSMESA_ACCUM_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_COMPAT_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  impl_->context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!impl_->context)
    throw RenderError(
        "OSMesaCreateContextAttribs failed: no OpenGL 3.3 compatibility context from OSMesa "
        "(is Debian's libosmesa6 installed?)");
  impl_->buffer.assign(static_cast<size_t>(width) * height * 4, 0);
  make_current();
}

OffscreenContext::~OffscreenContext() {
  if (impl_->context) {
    FpTrapsMasked masked;
    OSMesaDestroyContext(impl_->context);
  }
}

void OffscreenContext::make_current() {
  FpTrapsMasked masked;
  if (!OSMesaMakeCurrent(impl_->context, impl_->buffer.data(), GL_UNSIGNED_BYTE, width_, height_))
    throw RenderError("OSMesaMakeCurrent failed for a " + std::to_string(width_) + "x" +
                      std::to_string(height_) + " RGBA buffer");
}

void OffscreenContext::clear(float r, float g, float b, float a) {
  FpTrapsMasked masked;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width_, height_);
  glDisable(GL_SCISSOR_TEST);
  glClearColor(r, g, b, a);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

std::vector<uint8_t> OffscreenContext::read_rgba() {
  {
    FpTrapsMasked masked;
    glFinish();
  }
  const size_t row = static_cast<size_t>(width_) * 4;
  std::vector<uint8_t> out(row * height_);
  for (int y = 0; y < height_; ++y)
    std::memcpy(out.data() + row * y, impl_->buffer.data() + row * (height_ - 1 - y), row);
  return out;
}

std::string OffscreenContext::gl_version() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return s ? s : "";
}

std::string OffscreenContext::gl_renderer() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

// ---------------------------------------------------------------------------------------
// Fonts
// ---------------------------------------------------------------------------------------

std::string find_font(const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (name.find('/') != std::string::npos) {
    if (!fs::is_regular_file(name, ec)) throw RenderError(name + ": font file not found");
    return name;
  }
  std::vector<std::string> dirs;
  try {
    dirs.push_back(assets_dir() + "/fonts");
  } catch (const RenderError&) {  // no assets: the system's fonts may still do
  }
  dirs.push_back("/usr/share/fonts/truetype/dejavu");
  std::string tried;
  for (const std::string& d : dirs) {
    const std::string path = d + "/" + name;
    if (fs::is_regular_file(path, ec)) return path;
    tried += (tried.empty() ? "" : ", ") + d;
  }
  throw RenderError("font " + name + " not found in " + tried +
                    " (install fonts-dejavu-core or copy it into assets/fonts)");
}

// ---------------------------------------------------------------------------------------
// ImGuiLayer
// ---------------------------------------------------------------------------------------

namespace {

// Latin-1, Greek (α, σ, Δ), punctuation, super- and subscripts (10⁶, E₀), arrows and
// mathematical operators (−, ±, ≤): what axis labels and units need.
const ImWchar kGlyphRanges[] = {0x0020, 0x00FF, 0x0370, 0x03FF, 0x2000, 0x206F, 0x2070,
                                0x209F, 0x2190, 0x21FF, 0x2200, 0x22FF, 0};

}  // namespace

ImGuiLayer::ImGuiLayer(OffscreenContext& ctx, const std::vector<FontSpec>& fonts) : ctx_(ctx) {
  if (fonts.empty()) throw RenderError("ImGuiLayer needs at least one font");
  std::vector<std::string> paths;
  for (const FontSpec& f : fonts) {
    if (!(f.pixels >= 4.0f && f.pixels <= 512.0f))
      throw RenderError("font " + f.file + ": pixel size " + std::to_string(f.pixels) +
                        " is outside 4..512");
    paths.push_back(find_font(f.file));  // checked before ImGui, which asserts on failure
  }
  ImGuiContext* previous = ImGui::GetCurrentContext();
  imgui_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(imgui_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini, no log file
  io.LogFilename = nullptr;
  for (size_t i = 0; i < fonts.size(); ++i) {
    ImFontConfig config;
    config.OversampleH = 3;
    config.OversampleV = 2;
    ImFont* font =
        io.Fonts->AddFontFromFileTTF(paths[i].c_str(), fonts[i].pixels, &config, kGlyphRanges);
    if (!font) {
      ImGui::DestroyContext(imgui_);
      ImGui::SetCurrentContext(previous);
      throw RenderError(paths[i] + ": not a TrueType font ImGui can load");
    }
    fonts_.push_back(font);
  }
  ctx_.make_current();
  FpTrapsMasked masked;
  ImGui_ImplOpenGL2_Init();
}

ImGuiLayer::~ImGuiLayer() {
  ImGui::SetCurrentContext(imgui_);
  {
    FpTrapsMasked masked;
    ctx_.make_current();
    ImGui_ImplOpenGL2_Shutdown();
  }
  ImGui::DestroyContext(imgui_);
}

void ImGuiLayer::begin_frame() {
  if (in_frame_) throw RenderError("ImGuiLayer::begin_frame called twice without rendering");
  ctx_.make_current();
  ImGui::SetCurrentContext(imgui_);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(ctx_.width()), static_cast<float>(ctx_.height()));
  io.DisplayFramebufferScale = ImVec2(1, 1);
  io.DeltaTime = 1.0f / 30.0f;  // fixed: nothing here animates
  FpTrapsMasked masked;
  ImGui_ImplOpenGL2_NewFrame();  // uploads the font atlas on the first frame
  ImGui::NewFrame();
  in_frame_ = true;
}

ImDrawList* ImGuiLayer::draw_list() {
  if (!in_frame_) throw RenderError("ImGuiLayer::draw_list called outside begin/end_frame");
  return ImGui::GetBackgroundDrawList();
}

ImFont* ImGuiLayer::font(size_t i) const {
  if (i >= fonts_.size())
    throw RenderError("ImGuiLayer::font(" + std::to_string(i) + "): only " +
                      std::to_string(fonts_.size()) + " fonts loaded");
  return fonts_[i];
}

void ImGuiLayer::end_frame_and_render() {
  if (!in_frame_) throw RenderError("ImGuiLayer::end_frame_and_render without begin_frame");
  ImGui::SetCurrentContext(imgui_);
  ImGui::Render();
  FpTrapsMasked masked;
  // The OpenGL 2 backend draws with fixed-function GL and client-side arrays: unbind
  // whatever a shader-based pass left behind.
  glUseProgram(0);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glActiveTexture(GL_TEXTURE0);
  ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
  in_frame_ = false;
}

}  // namespace plastivox::render
