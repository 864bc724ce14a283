#include "limit_rig.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "loom/error.hpp"

namespace loom::shading {

namespace {

// One triangle covering the viewport (the usual full-screen "quad": no
// diagonal seam), at NDC depth u_depth.
const char* const fullscreen_vertex = R"(#version 450 core
uniform float u_depth;
void main() {
  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, u_depth, 1.0);
}
)";

// Vertex i of a u_columns x u_columns grid of 2 x 2-pixel cells from the
// viewport's corner: triangles of 2 pixels, ~450 pixels across for 100k of
// them, about the target frame's sphere (~430 pixels across, front and back
// faces drawn). Nearly all setup, little fill.
const char* const grid_vertex = R"(#version 450 core
uniform int u_columns;
uniform vec2 u_viewport;
uniform float u_depth;
void main() {
  vec2 g = vec2(gl_VertexID % u_columns, gl_VertexID / u_columns);
  gl_Position = vec4(g * 4.0 / u_viewport - 1.0, u_depth, 1.0);
}
)";

const char* const constant_fragment = R"(#version 450 core
layout(location = 0) out vec4 o_color;
void main() { o_color = vec4(0.2, 0.4, 0.6, 1.0); }
)";

const char* const no_output_fragment = "#version 450 core\nvoid main() {}\n";

// The Render node's PCF lookups alone (shader_sources.cpp, FILTER_PCF, 2D
// map): n x n texels by textureGather, 2 x 2 each, compared with a depth;
// one map texel per pixel, as on the target frame's floor.
std::string pcf_fragment(int n) {
  return "#version 450 core\n#define PCF_SIZE " + std::to_string(n) + R"(
uniform sampler2D u_map;
uniform float u_resolution;
layout(location = 0) out vec4 o_color;
void main() {
  const int n = PCF_SIZE;
  ivec2 t0 = ivec2(floor(gl_FragCoord.xy - 0.5 * float(n - 1)));
  float lit = 0.0;
  for (int gy = 0; gy < n; gy += 2)
    for (int gx = 0; gx < n; gx += 2) {
      vec4 z = textureGather(u_map, vec2(t0 + ivec2(gx + 1, gy + 1)) / u_resolution, 0);
      float wx = gx + 1 < n ? 1.0 : 0.0, wy = gy + 1 < n ? 1.0 : 0.0;
      lit += dot(vec4(greaterThanEqual(z, vec4(0.5))), vec4(wy, wx * wy, wx, 1.0));
    }
  o_color = vec4(vec3(lit / float(n * n)), 1.0);
}
)";
}

using Stages = std::vector<std::pair<GLenum, const char*>>;

Framebuffer make_framebuffer(const GlApi& gl, int W, int H, int samples, bool color) {
  Framebuffer f{W, H, color};
  const GLenum target = samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
  auto storage = [&](GLuint& texture, GLenum format) {
    gl.CreateTextures(target, 1, &texture);
    if (samples > 1)
      gl.TextureStorage2DMultisample(texture, samples, format, W, H, GL_TRUE);
    else
      gl.TextureStorage2D(texture, 1, format, W, H);
  };
  gl.CreateFramebuffers(1, &f.fbo);
  if (color) {
    storage(f.color_texture, GL_RGBA16F);
    gl.NamedFramebufferTexture(f.fbo, GL_COLOR_ATTACHMENT0, f.color_texture, 0);
  }
  storage(f.depth_texture, GL_DEPTH_COMPONENT32F);
  gl.NamedFramebufferTexture(f.fbo, GL_DEPTH_ATTACHMENT, f.depth_texture, 0);
  const GLenum draw = color ? GL_COLOR_ATTACHMENT0 : GL_NONE;
  gl.NamedFramebufferDrawBuffers(f.fbo, 1, &draw);
  if (gl.CheckNamedFramebufferStatus(f.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("limit framebuffer " + std::to_string(W) + "x" + std::to_string(H) + " is incomplete");
  return f;
}

}  // namespace

LimitRig::LimitRig(const RenderFrame& f) : render_(f) {
  GlContext::Current current(context_);
  const GlApi& gl = context_.gl();
  image_ = make_framebuffer(gl, f.width, f.height, 1, true);
  image_msaa_ = make_framebuffer(gl, f.width, f.height, f.samples, true);
  shadow_map_ = make_framebuffer(gl, f.shadow_resolution, f.shadow_resolution, 1, false);
  // Sampled by the PCF runs as Render samples its directional map.
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER})
    gl.TextureParameteri(shadow_map_.depth_texture, p, GL_NEAREST);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T})
    gl.TextureParameteri(shadow_map_.depth_texture, p, GL_CLAMP_TO_BORDER);
  const std::string pcf = pcf_fragment(f.pcf_size);
  for (int g = 0; g < 2; ++g) {
    const char* vertex = g ? grid_vertex : fullscreen_vertex;
    programs_[g][0] = std::make_unique<GlProgram>(
        gl, "limit constant", Stages{{GL_VERTEX_SHADER, vertex}, {GL_FRAGMENT_SHADER, constant_fragment}});
    programs_[g][1] = std::make_unique<GlProgram>(
        gl, "limit depth", Stages{{GL_VERTEX_SHADER, vertex}, {GL_FRAGMENT_SHADER, no_output_fragment}});
  }
  programs_[0][2] = std::make_unique<GlProgram>(
      gl, "limit pcf", Stages{{GL_VERTEX_SHADER, fullscreen_vertex}, {GL_FRAGMENT_SHADER, pcf.c_str()}});
  // n x n cells of two triangles: 2 n² close to the frame's triangle count.
  const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(f.triangles / 2.0))));
  grid_columns_ = n + 1;
  std::vector<GLuint> indices, half_culled;
  indices.reserve(6 * std::size_t(n) * n);
  half_culled.reserve(indices.capacity());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const GLuint a = GLuint(y * grid_columns_ + x), b = a + 1, c = a + GLuint(grid_columns_), d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});
      half_culled.insert(half_culled.end(), {a, b, d, a, c, d});
    }
  grid_indices_ = static_cast<GLsizei>(indices.size());
  gl.CreateVertexArrays(1, &empty_vao_);
  gl.CreateVertexArrays(1, &grid_vao_);
  for (auto [buffer, data] : {std::pair{&grid_buffer_, &indices}, std::pair{&grid_half_culled_buffer_, &half_culled}}) {
    gl.CreateBuffers(1, buffer);
    gl.NamedBufferData(*buffer, static_cast<GLsizeiptr>(data->size() * sizeof(GLuint)), data->data(), GL_STATIC_DRAW);
  }
  gl.check("setting up the limit runs");
}

LimitRig::~LimitRig() {
  GlContext::Current current(context_);
  const GlApi& gl = context_.gl();
  for (auto& row : programs_)
    for (auto& p : row) p.reset();
  for (Framebuffer* f : {&image_, &image_msaa_, &shadow_map_}) {
    gl.DeleteFramebuffers(1, &f->fbo);
    if (f->color_texture) gl.DeleteTextures(1, &f->color_texture);
    gl.DeleteTextures(1, &f->depth_texture);
  }
  gl.DeleteBuffers(1, &grid_buffer_);
  gl.DeleteBuffers(1, &grid_half_culled_buffer_);
  gl.DeleteVertexArrays(1, &grid_vao_);
  gl.DeleteVertexArrays(1, &empty_vao_);
}

const Framebuffer& LimitRig::framebuffer(Target t) const {
  return t == Target::shadow_map ? shadow_map_ : t == Target::image ? image_ : image_msaa_;
}

long long LimitRig::pixels(Target t) const {
  return static_cast<long long>(framebuffer(t).width) * framebuffer(t).height;
}

GlProgram& LimitRig::program(bool grid, Shading s) { return *programs_[grid ? 1 : 0][static_cast<int>(s)]; }

void LimitRig::frame(Target t, GlProgram& p, bool depth_test, const std::function<void()>& draw, int draws) {
  const GlApi& gl = context_.gl();
  const Framebuffer& f = framebuffer(t);
  gl.BindFramebuffer(GL_FRAMEBUFFER, f.fbo);
  gl.Viewport(0, 0, f.width, f.height);
  const float background[4] = {0.1f, 0.1f, 0.1f, 0}, far_depth = 1;
  if (f.color) gl.ClearBufferfv(GL_COLOR, 0, background);
  gl.ClearBufferfv(GL_DEPTH, 0, &far_depth);
  if (depth_test)
    gl.Enable(GL_DEPTH_TEST);
  else
    gl.Disable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  gl.Disable(GL_CULL_FACE);
  gl.Disable(GL_BLEND);
  p.use();
  p.set("u_map", 0);
  p.set("u_resolution", static_cast<double>(render_.shadow_resolution));
  gl.BindTextureUnit(0, t == Target::shadow_map ? 0 : shadow_map_.depth_texture);
  for (int k = 0; k < draws; ++k) {
    // Each draw nearer than the last: every fragment passes GL_LESS and writes.
    p.set("u_depth", 0.9 - 1.8 * (k + 1) / (draws + 1));
    draw();
  }
  gl.Finish();
  gl.BindTextureUnit(0, 0);
  gl.check("a limit frame");
}

void LimitRig::quads(Target t, Shading s, int quads) {
  GlContext::Current current(context_);
  const GlApi& gl = context_.gl();
  gl.BindVertexArray(empty_vao_);
  frame(
      t, program(false, s), t == Target::shadow_map, [&] { gl.DrawArrays(GL_TRIANGLES, 0, 3); }, quads);
}

void LimitRig::grid(Target t, Shading s, bool half_culled) {
  GlContext::Current current(context_);
  const GlApi& gl = context_.gl();
  GlProgram& p = program(true, s);
  gl.VertexArrayElementBuffer(grid_vao_, half_culled ? grid_half_culled_buffer_ : grid_buffer_);
  gl.BindVertexArray(grid_vao_);
  p.use();
  p.set("u_columns", grid_columns_);
  const long long side = t == Target::shadow_map ? render_.shadow_resolution : 0;
  p.set("u_viewport", side ? Eigen::Vector2d(side, side) : Eigen::Vector2d(render_.width, render_.height));
  frame(
      t, p, true,
      [&] {
        gl.CullFace(GL_BACK);
        if (half_culled) gl.Enable(GL_CULL_FACE);
        gl.DrawElements(GL_TRIANGLES, grid_indices_, GL_UNSIGNED_INT, nullptr);
        gl.Disable(GL_CULL_FACE);
      },
      1);
}

}  // namespace loom::shading
