// The GL corner of the renderer: shaders, instanced voxel boxes, floor, the world's ground and
// obstacles, shadow map and the multisampled target (see scene.hpp). Everything else builds
// plain Scene data.
//
// Passes per draw():
//   1. shadow map: depth of the boxes seen from the key light (orthographic, fitted to the
//      boxes' bounding sphere), 2048^2, sampled with hardware comparison and 16 taps;
//   2. colour: background clear, boxes (instanced, front to back), floor (grid, shadow,
//      fade) or the environment's ground, and obstacle boxes (world_triangles, the floor's
//      grid, shadow and fade, lit by their faces' normals), into a framebuffer of the viewport's
//      size: one sample per pixel (edge anti-aliasing, the default; or no anti-aliasing) or
//      multisampled;
//   3. into the viewport of the default framebuffer (OSMesa's image): the edge
//      anti-aliasing pass (edge_aa.frag) reading the one-sample image, or a blit (resolving
//      the samples).
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "fp_guard.hpp"
#include "plastivox/render/assets.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/scene.hpp"

namespace plastivox::render {
namespace {

constexpr int kShadowSize = 2048;

// Throws `what` with GL's log, the object deleted, unless its `status` (GL_COMPILE_STATUS of a
// shader, GL_LINK_STATUS of a program) is set; get_iv, get_log and remove are the calls for
// that kind of object (glGetShaderiv, glGetShaderInfoLog, glDeleteShader or the Program ones).
void check_built(GLuint object, GLenum status, void (*get_iv)(GLuint, GLenum, GLint*),
                 void (*get_log)(GLuint, GLsizei, GLsizei*, GLchar*), void (*remove)(GLuint),
                 const std::string& what) {
  GLint ok = 0;
  get_iv(object, status, &ok);
  if (ok) return;
  std::array<char, 2048> log{};
  get_log(object, static_cast<GLsizei>(log.size()), nullptr, log.data());
  remove(object);
  throw RenderError(what + ": " + std::string(log.data()));
}

GLuint compile_shader(GLenum type, const std::string& source, const std::string& name) {
  const GLuint sh = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(sh, 1, &text, nullptr);
  glCompileShader(sh);
  check_built(sh, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
              "shader " + name + " does not compile");
  return sh;
}

// Program from assets/shaders/<name>.vert and .frag, with `defines` (#define lines) and
// common.glsl (and, for fragment shaders, shadow_lookup.glsl and grid.glsl) prepended.
GLuint load_program(const std::string& name, const std::string& defines = "") {
  const std::string header = "#version 330 core\n" + defines;
  const std::string common = read_asset("shaders/common.glsl");
  const std::string lookup =
      read_asset("shaders/shadow_lookup.glsl") + read_asset("shaders/grid.glsl");
  const GLuint vs = compile_shader(
      GL_VERTEX_SHADER, header + common + read_asset("shaders/" + name + ".vert"), name + ".vert");
  const GLuint fs = compile_shader(
      GL_FRAGMENT_SHADER, header + common + lookup + read_asset("shaders/" + name + ".frag"),
      name + ".frag");
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, vs);
  glAttachShader(prog, fs);
  glBindFragDataLocation(prog, 0, "frag_color");
  glLinkProgram(prog);
  glDeleteShader(vs);
  glDeleteShader(fs);
  check_built(prog, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
              "shader program " + name + " does not link");
  return prog;
}

// Column-major float copy of a double matrix, as glUniformMatrix4fv wants.
std::array<float, 16> to_gl(const Eigen::Matrix4d& m) {
  std::array<float, 16> out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = static_cast<float>(m(r, c));
  return out;
}

void set_matrix(GLuint prog, const char* name, const Eigen::Matrix4d& m) {
  const auto a = to_gl(m);
  glUniformMatrix4fv(glGetUniformLocation(prog, name), 1, GL_FALSE, a.data());
}
void set_vec3(GLuint prog, const char* name, const Eigen::Vector3d& v) {
  glUniform3f(glGetUniformLocation(prog, name), static_cast<float>(v.x()),
              static_cast<float>(v.y()), static_cast<float>(v.z()));
}
void set_rgb(GLuint prog, const char* name, const Rgb8& c) {
  glUniform3f(glGetUniformLocation(prog, name), c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f);
}
// An sRGB colour as linear-light components (uniforms the shaders light with).
void set_linear(GLuint prog, const char* name, const Rgb8& c) {
  auto lin = [](int v) {
    const double x = v / 255.0;
    return static_cast<float>(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
  };
  glUniform3f(glGetUniformLocation(prog, name), lin(c[0]), lin(c[1]), lin(c[2]));
}
void set_float(GLuint prog, const char* name, double v) {
  glUniform1f(glGetUniformLocation(prog, name), static_cast<float>(v));
}
void set_int(GLuint prog, const char* name, int v) {
  glUniform1i(glGetUniformLocation(prog, name), v);
}

// The unit cube as 6 faces x 4 corners with outward normals, and its 36 indices.
// A vertex array and its vertex buffer, made and bound.
void make_vertex_array(GLuint& vao, GLuint& vbo) {
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
}

// Vertex attribute `index` of the bound buffer: `count` floats at `offset` floats into each
// record of `stride` floats.
void float_attribute(GLuint index, int count, int stride, int offset) {
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, count, GL_FLOAT, GL_FALSE, stride * sizeof(float),
                        reinterpret_cast<void*>(offset * sizeof(float)));
}

void cube_mesh(std::vector<float>& vertices, std::vector<GLushort>& indices) {
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const GLushort base = static_cast<GLushort>(vertices.size() / 6);
      for (int k = 0; k < 4; ++k) {
        float p[3], n[3] = {0, 0, 0};
        p[axis] = 0.5f * sign;
        p[u] = (k == 1 || k == 2) ? 0.5f : -0.5f;
        p[v] = (k >= 2) ? 0.5f : -0.5f;
        n[axis] = static_cast<float>(sign);
        vertices.insert(vertices.end(), {p[0], p[1], p[2], n[0], n[1], n[2]});
      }
      // Counter-clockwise seen from outside.
      if (sign > 0)
        indices.insert(indices.end(),
                       {base, static_cast<GLushort>(base + 1), static_cast<GLushort>(base + 2),
                        base, static_cast<GLushort>(base + 2), static_cast<GLushort>(base + 3)});
      else
        indices.insert(indices.end(),
                       {base, static_cast<GLushort>(base + 2), static_cast<GLushort>(base + 1),
                        base, static_cast<GLushort>(base + 3), static_cast<GLushort>(base + 2)});
    }
}

// The rectangle (lo, hi) of the surfaces between the levels z_lo and z_hi (the floor plane
// z = 0: both 0) where the boxes inside the box (box_lo, box_hi) can cast a shadow from a
// light in direction `light` (unit, towards the light, light.z > 0): the bounding rectangle of
// the box's corners moved along the light onto either level (a surface between them catches
// the shadow between the two), and of the box's own footprint, with a margin for the filter's
// blur. Returns false if the light grazes the floor (then no rectangle bounds the shadow).
bool shadow_footprint(const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi,
                      const Eigen::Vector3d& light, double z_lo, double z_hi, Eigen::Vector2d& lo,
                      Eigen::Vector2d& hi) {
  if (light.z() < 0.05) return false;
  Eigen::Vector2d l = Eigen::Vector2d::Constant(1e30), h = -l;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c((k & 1) ? box_hi.x() : box_lo.x(), (k & 2) ? box_hi.y() : box_lo.y(),
                            (k & 4) ? box_hi.z() : box_lo.z());
    // The corner's shadow on each level, and the corner itself (its drop: 0).
    for (const double drop : {c.z() - z_lo, c.z() - z_hi, 0.0}) {
      const Eigen::Vector2d p = c.head<2>() - std::max(drop, 0.0) / light.z() * light.head<2>();
      l = l.cwiseMin(p);
      h = h.cwiseMax(p);
    }
  }
  const double margin = 0.05 * (h - l).maxCoeff() + 1e-6;
  lo = l.array() - margin;
  hi = h.array() + margin;
  return true;
}

// The floor square (half-size `half` about `centre`, z = 0) cut into a 3x3 grid of quads by
// the rectangle (lo, hi), clamped into the square; the middle quad first. Neighbouring
// quads share whole edges (no T-junctions), so rasterization leaves no cracks between them.
// Two triangles (x, y, 0 per corner) per quad: 54 vertices.
std::vector<float> floor_pieces(const Eigen::Vector2d& centre, double half, Eigen::Vector2d lo,
                                Eigen::Vector2d hi) {
  const Eigen::Vector2d a = centre.array() - half, b = centre.array() + half;
  lo = lo.cwiseMax(a).cwiseMin(b);
  hi = hi.cwiseMax(lo).cwiseMin(b);
  const double xs[4] = {a.x(), lo.x(), hi.x(), b.x()}, ys[4] = {a.y(), lo.y(), hi.y(), b.y()};
  std::vector<float> out;
  out.reserve(54 * 3);
  auto quad = [&](int i, int j) {
    const float x0 = static_cast<float>(xs[i]), x1 = static_cast<float>(xs[i + 1]);
    const float y0 = static_cast<float>(ys[j]), y1 = static_cast<float>(ys[j + 1]);
    out.insert(out.end(), {x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y0, 0, x1, y1, 0, x0, y1, 0});
  };
  quad(1, 1);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      if (i != 1 || j != 1) quad(i, j);
  return out;
}

}  // namespace

struct SceneRenderer::Impl {
  OffscreenContext* ctx = nullptr;
  GLuint box_prog = 0, floor_prog = 0, floor_plain_prog = 0, shadow_prog = 0;
  GLuint world_prog = 0, world_plain_prog = 0, edge_prog = 0, edge_detect_prog = 0;
  GLuint box_vao = 0, floor_vao = 0, world_vao = 0, edge_vao = 0;
  GLuint cube_vbo = 0, cube_ibo = 0, instance_vbo = 0, floor_vbo = 0, world_vbo = 0, edge_vbo = 0;
  GLuint shadow_fbo = 0, shadow_tex = 0;
  // The colour target: a renderbuffer (multisampled or not), or for edge anti-aliasing a
  // texture the edge pass reads.
  GLuint target_fbo = 0, target_color = 0, target_texture = 0, target_depth = 0;
  int target_w = 0, target_h = 0, target_samples = -1;

  void release_target() {
    if (!target_fbo) return;
    glDeleteFramebuffers(1, &target_fbo);
    if (target_color) glDeleteRenderbuffers(1, &target_color);
    if (target_texture) glDeleteTextures(1, &target_texture);
    glDeleteRenderbuffers(1, &target_depth);
    target_fbo = target_color = target_texture = target_depth = 0;
  }

  // samples: kEdgeAntialiasing (one sample, colour in a texture), 1, or 2..8.
  void ensure_target(int w, int h, int samples) {
    if (w == target_w && h == target_h && samples == target_samples) return;
    release_target();
    glGenFramebuffers(1, &target_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, target_fbo);
    if (samples == kEdgeAntialiasing) {
      glGenTextures(1, &target_texture);
      glBindTexture(GL_TEXTURE_2D, target_texture);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      glBindTexture(GL_TEXTURE_2D, 0);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target_texture,
                             0);
    } else {
      glGenRenderbuffers(1, &target_color);
      glBindRenderbuffer(GL_RENDERBUFFER, target_color);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples > 1 ? samples : 0, GL_RGBA8, w, h);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                target_color);
    }
    glGenRenderbuffers(1, &target_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, target_depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples > 1 ? samples : 0,
                                     GL_DEPTH_COMPONENT24, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, target_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("the " + std::to_string(w) + "x" + std::to_string(h) + " render target (" +
                        std::to_string(samples) + " samples) is not supported by this OpenGL");
    target_w = w;
    target_h = h;
    target_samples = samples;
  }
};

SceneRenderer::SceneRenderer(OffscreenContext& ctx) : impl_(std::make_unique<Impl>()) {
  Impl& g = *impl_;
  g.ctx = &ctx;
  ctx.make_current();
  FpTrapsMasked masked;
  g.box_prog = load_program("box");
  g.floor_prog = load_program("floor");
  g.floor_plain_prog = load_program("floor", "#define FLOOR_UNSHADOWED 1\n");
  g.world_prog = load_program("world");
  g.world_plain_prog = load_program("world", "#define WORLD_UNSHADOWED 1\n");
  g.shadow_prog = load_program("shadow");
  g.edge_prog = load_program("edge_aa");
  g.edge_detect_prog = load_program("edge_aa", "#define EDGE_DETECT 1\n");

  std::vector<float> verts;
  std::vector<GLushort> idx;
  cube_mesh(verts, idx);
  make_vertex_array(g.box_vao, g.cube_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(float)), verts.data(),
               GL_STATIC_DRAW);
  float_attribute(0, 3, 6, 0);  // position
  float_attribute(1, 3, 6, 3);  // normal
  glGenBuffers(1, &g.cube_ibo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.cube_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(GLushort)),
               idx.data(), GL_STATIC_DRAW);
  // Per-instance: centre (3), orientation (4), edge (1), colour (3) = 11 floats.
  glGenBuffers(1, &g.instance_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.instance_vbo);
  const int sizes[] = {3, 4, 1, 3};
  int offset = 0;
  for (int a = 0; a < 4; ++a) {
    float_attribute(2 + a, sizes[a], 11, offset);
    glVertexAttribDivisor(2 + a, 1);
    offset += sizes[a];
  }

  // Floor pieces are world positions, uploaded with each scene.
  make_vertex_array(g.floor_vao, g.floor_vbo);
  float_attribute(0, 3, 3, 0);

  // The world's triangles (world_triangles: position and normal per corner), per scene.
  make_vertex_array(g.world_vao, g.world_vbo);
  float_attribute(0, 3, 6, 0);
  float_attribute(1, 3, 6, 3);

  // One triangle covering the viewport, for the edge anti-aliasing pass.
  const float cover[] = {-1, -1, 0, 3, -1, 0, -1, 3, 0};
  make_vertex_array(g.edge_vao, g.edge_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof cover, cover, GL_STATIC_DRAW);
  float_attribute(0, 3, 3, 0);
  glBindVertexArray(0);

  glGenTextures(1, &g.shadow_tex);
  glBindTexture(GL_TEXTURE_2D, g.shadow_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, kShadowSize, kShadowSize, 0,
               GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &g.shadow_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, g.shadow_fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, g.shadow_tex, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the shadow-map framebuffer is not supported by this OpenGL");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

SceneRenderer::~SceneRenderer() {
  Impl& g = *impl_;
  g.ctx->make_current();
  FpTrapsMasked masked;
  glDeleteProgram(g.box_prog);
  glDeleteProgram(g.floor_prog);
  glDeleteProgram(g.floor_plain_prog);
  glDeleteProgram(g.shadow_prog);
  glDeleteProgram(g.world_prog);
  glDeleteProgram(g.world_plain_prog);
  glDeleteProgram(g.edge_prog);
  glDeleteProgram(g.edge_detect_prog);
  const GLuint buffers[] = {g.cube_vbo,  g.cube_ibo,  g.instance_vbo,
                            g.floor_vbo, g.world_vbo, g.edge_vbo};
  glDeleteBuffers(6, buffers);
  const GLuint vaos[] = {g.box_vao, g.floor_vao, g.world_vao, g.edge_vao};
  glDeleteVertexArrays(4, vaos);
  glDeleteFramebuffers(1, &g.shadow_fbo);
  glDeleteTextures(1, &g.shadow_tex);
  g.release_target();
}

void SceneRenderer::draw(const Scene& scene, PixelRect vp) {
  Impl& g = *impl_;
  OffscreenContext& ctx = *g.ctx;
  if (vp.width <= 0) vp = {0, 0, ctx.width(), ctx.height()};
  if (vp.x < 0 || vp.y < 0 || vp.height <= 0 || vp.x + vp.width > ctx.width() ||
      vp.y + vp.height > ctx.height())
    throw RenderError("viewport outside the image");
  ctx.make_current();
  FpTrapsMasked masked;
  const int samples =
      scene.samples == kEdgeAntialiasing ? kEdgeAntialiasing : std::clamp(scene.samples, 1, 8);
  g.ensure_target(vp.width, vp.height, samples);

  // Instance data. An orthographic eye is moved back far enough that nothing near the
  // target is clipped.
  // Boxes go front to back, so llvmpipe's early depth test skips hidden fragments (ties
  // broken by index: a total order, the same every time).
  Camera cam = scene.camera;
  if (cam.orthographic) cam.distance = std::max(cam.distance, 2.0 * cam.ortho_height);
  const Eigen::Vector3f eye = cam.eye().cast<float>();
  std::vector<std::pair<float, size_t>> order(scene.boxes.size());
  for (size_t i = 0; i < scene.boxes.size(); ++i)
    order[i] = {(scene.boxes[i].center - eye).squaredNorm(), i};
  std::sort(order.begin(), order.end());
  std::vector<float> inst;
  inst.reserve(scene.boxes.size() * 11);
  Eigen::Vector3d lo3 = Eigen::Vector3d::Constant(1e30), hi3 = -lo3;  // the boxes' bounds
  for (const auto& [depth, index] : order) {
    const Box& b = scene.boxes[index];
    const Eigen::Quaternionf q = b.orient.normalized();
    inst.insert(inst.end(),
                {b.center.x(), b.center.y(), b.center.z(), q.x(), q.y(), q.z(), q.w(), b.edge,
                 b.color[0] / 255.0f, b.color[1] / 255.0f, b.color[2] / 255.0f});
    const Eigen::Vector3d c = b.center.cast<double>();
    lo3 = lo3.cwiseMin(c - Eigen::Vector3d::Constant(b.edge));
    hi3 = hi3.cwiseMax(c + Eigen::Vector3d::Constant(b.edge));
  }
  const GLsizei count = static_cast<GLsizei>(scene.boxes.size());
  glBindBuffer(GL_ARRAY_BUFFER, g.instance_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(inst.size() * sizeof(float)),
               inst.empty() ? nullptr : inst.data(), GL_STREAM_DRAW);

  const double aspect = static_cast<double>(vp.width) / vp.height;
  const double reach = cam.distance;
  const Eigen::Matrix4d view_proj = cam.view_projection(aspect, reach * 0.02, reach * 40);
  const Eigen::Vector3d light = scene.light_dir.normalized();

  // 1. Shadow map, fitted to the boxes' bounding sphere.
  Eigen::Matrix4d light_vp = Eigen::Matrix4d::Identity();
  const bool shadows = scene.shadows && scene.lit && count > 0;
  if (shadows) {
    const Eigen::Vector3d centre = 0.5 * (lo3 + hi3);
    const double radius = 0.5 * (hi3 - lo3).norm() * 1.1;
    Camera lc;
    lc.target = centre;
    lc.orthographic = true;
    lc.ortho_height = 2 * radius;
    lc.distance = 4 * radius;
    lc.azimuth_deg = std::atan2(light.y(), light.x()) * 180 / 3.14159265358979323846;
    lc.elevation_deg = std::asin(std::clamp(light.z(), -1.0, 1.0)) * 180 / 3.14159265358979323846;
    light_vp = lc.view_projection(1.0, 0.5 * radius, 8 * radius);
    glBindFramebuffer(GL_FRAMEBUFFER, g.shadow_fbo);
    glViewport(0, 0, kShadowSize, kShadowSize);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 2.0f);
    glUseProgram(g.shadow_prog);
    set_matrix(g.shadow_prog, "u_view_proj", light_vp);
    glBindVertexArray(g.box_vao);
    glDrawElementsInstanced(GL_TRIANGLES, 36, GL_UNSIGNED_SHORT, nullptr, count);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }

  // 2. Colour pass into the (multisampled) target.
  glBindFramebuffer(GL_FRAMEBUFFER, g.target_fbo);
  glViewport(0, 0, vp.width, vp.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glClearColor(scene.background[0] / 255.0f, scene.background[1] / 255.0f,
               scene.background[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, g.shadow_tex);
  auto common_uniforms = [&](GLuint prog) {
    glUseProgram(prog);
    set_matrix(prog, "u_view_proj", view_proj);
    set_matrix(prog, "u_light_view_proj", light_vp);
    set_int(prog, "u_shadow_map", 0);
    set_int(prog, "u_shadows", shadows ? 1 : 0);
    set_float(prog, "u_shadow_texel", 1.0 / kShadowSize);
    set_int(prog, "u_lit", scene.lit ? 1 : 0);
    set_vec3(prog, "u_light_dir", light);
  };
  if (count > 0) {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    common_uniforms(g.box_prog);
    set_int(g.box_prog, "u_outlines", scene.outlines ? 1 : 0);
    set_vec3(g.box_prog, "u_eye", cam.eye());
    glBindVertexArray(g.box_vao);
    glDrawElementsInstanced(GL_TRIANGLES, 36, GL_UNSIGNED_SHORT, nullptr, count);
    glDisable(GL_CULL_FACE);
  }

  // The floor after the boxes: the depth test then skips the floor behind the robot. Only
  // the part the shadow map covers is drawn with the shadow lookup; llvmpipe runs both sides
  // of a branch, so a lookup skipped by a test in the shader would still cost its 16 taps.
  const double fade = reach * 2.5;
  const Eigen::Vector2d centre = cam.target.head<2>();
  // The shadowed rectangle on the surfaces between the levels z_lo and z_hi: empty without
  // shadows, everything drawn if the light grazes the floor.
  const auto shadowed = [&](double z_lo, double z_hi, Eigen::Vector2d& lo, Eigen::Vector2d& hi) {
    lo = hi = centre;
    if (shadows && !shadow_footprint(lo3, hi3, light, z_lo, z_hi, lo, hi)) {
      lo = centre.array() - fade;
      hi = centre.array() + fade;
    }
  };
  if (scene.floor && !scene.ground) {
    glDisable(GL_CULL_FACE);
    Eigen::Vector2d lo, hi;
    shadowed(0.0, 0.0, lo, hi);
    const std::vector<float> pieces = floor_pieces(centre, fade, lo, hi);
    glBindBuffer(GL_ARRAY_BUFFER, g.floor_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(pieces.size() * sizeof(float)),
                 pieces.data(), GL_STREAM_DRAW);
    glBindVertexArray(g.floor_vao);
    for (const GLuint prog : {g.floor_prog, g.floor_plain_prog}) {
      common_uniforms(prog);
      set_vec3(prog, "u_target", cam.target);
      set_float(prog, "u_fade", fade);
      set_float(prog, "u_grid", scene.grid_spacing);
      set_rgb(prog, "u_floor_color", scene.floor_color);
      set_linear(prog, "u_floor_linear", scene.floor_color);
      set_linear(prog, "u_background_linear", scene.background);
      if (prog == g.floor_prog)
        glDrawArrays(GL_TRIANGLES, 0, 6);  // the middle piece
      else
        glDrawArrays(GL_TRIANGLES, 6, 48);
    }
  }
  // The world beyond the floor: the ground (instead of the floor) and obstacle boxes, as
  // runs of triangles under the robot's shadow (drawn with the lookup) and not.
  const HeightField* ground = scene.floor ? scene.ground : nullptr;  // obstacles stand alone
  if (ground || !scene.obstacles.empty()) {
    double z_lo = 0, z_hi = 0;  // levels the surfaces span
    if (ground) {
      const auto [min_h, max_h] = std::minmax_element(ground->h.begin(), ground->h.end());
      z_lo = *min_h;
      z_hi = *max_h;
    }
    for (const ObstacleBox& box : scene.obstacles) {
      z_lo = std::min(z_lo, box.min[2]);
      z_hi = std::max(z_hi, box.max[2]);
    }
    Eigen::Vector2d lo, hi;
    shadowed(z_lo, z_hi, lo, hi);
    const WorldTriangles tri = world_triangles(ground, scene.obstacles, centre, fade, lo, hi);
    glDisable(GL_CULL_FACE);
    glBindBuffer(GL_ARRAY_BUFFER, g.world_vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(tri.corners.size() * sizeof(float)),
                 tri.corners.empty() ? nullptr : tri.corners.data(), GL_STREAM_DRAW);
    glBindVertexArray(g.world_vao);
    int first = 0;
    for (int run = 0; run < 4; ++run) {
      const GLuint prog = run % 2 == 0 ? g.world_prog : g.world_plain_prog;
      const Rgb8& color = run < 2 ? scene.floor_color : scene.obstacle_color;
      if (tri.counts[run] > 0) {
        common_uniforms(prog);
        set_vec3(prog, "u_target", cam.target);
        set_float(prog, "u_fade", fade);
        set_float(prog, "u_grid", scene.grid_spacing);
        set_rgb(prog, "u_color", color);
        set_linear(prog, "u_color_linear", color);
        set_linear(prog, "u_background_linear", scene.background);
        glDrawArrays(GL_TRIANGLES, first, tri.counts[run]);
      }
      first += tri.counts[run];
    }
  }
  // 3. Into the viewport of OSMesa's image (GL rows count from the bottom).
  const int y0 = ctx.height() - vp.y - vp.height;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, g.target_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glBlitFramebuffer(0, 0, vp.width, vp.height, vp.x, y0, vp.x + vp.width, y0 + vp.height,
                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (samples == kEdgeAntialiasing) {
    // Edge pixels are marked in the stencil buffer (1), then only they are redrawn.
    glViewport(vp.x, y0, vp.width, vp.height);
    glEnable(GL_SCISSOR_TEST);
    glScissor(vp.x, y0, vp.width, vp.height);
    glStencilMask(0xFF);
    glClearStencil(0);
    glClear(GL_STENCIL_BUFFER_BIT);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.target_texture);
    glBindVertexArray(g.edge_vao);
    for (const GLuint prog : {g.edge_detect_prog, g.edge_prog}) {
      const bool detect = prog == g.edge_detect_prog;
      glUseProgram(prog);
      set_int(prog, "u_image", 0);
      glUniform2i(glGetUniformLocation(prog, "u_size"), vp.width, vp.height);
      glUniform2f(glGetUniformLocation(prog, "u_origin"), static_cast<float>(vp.x),
                  static_cast<float>(y0));
      glColorMask(!detect, !detect, !detect, !detect);
      glStencilFunc(detect ? GL_ALWAYS : GL_EQUAL, 1, 0xFF);
      glStencilOp(GL_KEEP, GL_KEEP, detect ? GL_REPLACE : GL_KEEP);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_SCISSOR_TEST);
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_DEPTH_TEST);
  glViewport(0, 0, ctx.width(), ctx.height());
}

}  // namespace plastivox::render
