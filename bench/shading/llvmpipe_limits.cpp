#include "llvmpipe_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "alternating.hpp"
#include "bench_harness.hpp"
#include "gl_context.hpp"
#include "gl_program.hpp"
#include "loom/error.hpp"

namespace loom::shading {

namespace {

using loom::bench::Csv;

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

// A framebuffer like Render's: RGBA16F colour (none for a depth map) and a
// 32-bit float depth buffer. The depth buffer is attached also where the
// depth test is off: without one, llvmpipe drops every earlier command of a
// tile an opaque triangle covers, and N full-screen quads would cost one.
struct Framebuffer {
  int width = 0, height = 0;
  bool color = true;
  GLuint fbo = 0, color_texture = 0, depth_texture = 0;
};

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

// The GL objects of the limit runs, in a context of their own (OSMesa, the
// same attributes as Render's: GlContext).
class LimitRig {
 public:
  enum class Target { image, image_msaa, shadow_map };
  enum class Shading { constant, depth_only, pcf };

  explicit LimitRig(const RenderFrame& f);
  ~LimitRig();
  LimitRig(const LimitRig&) = delete;
  LimitRig& operator=(const LimitRig&) = delete;

  // One frame: clear, `quads` full-screen triangles each nearer than the
  // last (depth test GL_LESS for the shadow map, off for the image), glFinish.
  void quads(Target t, Shading s, int quads);
  // One frame: clear, the grid of small triangles once (depth test on, as
  // Render's), glFinish.
  void grid(Target t, Shading s);
  long long grid_triangles() const { return grid_indices_ / 3; }
  long long pixels(Target t) const;

 private:
  void frame(Target t, GlProgram& p, bool depth_test, const std::function<void()>& draw, int draws);
  GlProgram& program(bool grid, Shading s);
  const Framebuffer& framebuffer(Target t) const;

  GlContext context_;
  RenderFrame render_;
  Framebuffer image_, image_msaa_, shadow_map_;
  std::unique_ptr<GlProgram> programs_[2][3];  // [grid][shading]; the grid has no PCF
  GLuint empty_vao_ = 0, grid_vao_ = 0, grid_buffer_ = 0;
  int grid_columns_ = 0;
  GLsizei grid_indices_ = 0;
};

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
  std::vector<GLuint> indices;
  indices.reserve(6 * std::size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const GLuint a = GLuint(y * grid_columns_ + x), b = a + 1, c = a + GLuint(grid_columns_), d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});
    }
  grid_indices_ = static_cast<GLsizei>(indices.size());
  gl.CreateVertexArrays(1, &empty_vao_);
  gl.CreateVertexArrays(1, &grid_vao_);
  gl.CreateBuffers(1, &grid_buffer_);
  gl.NamedBufferData(grid_buffer_, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)), indices.data(),
                     GL_STATIC_DRAW);
  gl.VertexArrayElementBuffer(grid_vao_, grid_buffer_);
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

void LimitRig::grid(Target t, Shading s) {
  GlContext::Current current(context_);
  const GlApi& gl = context_.gl();
  GlProgram& p = program(true, s);
  gl.BindVertexArray(grid_vao_);
  p.use();
  p.set("u_columns", grid_columns_);
  const long long side = t == Target::shadow_map ? render_.shadow_resolution : 0;
  p.set("u_viewport", side ? Eigen::Vector2d(side, side) : Eigen::Vector2d(render_.width, render_.height));
  frame(
      t, p, true, [&] { gl.DrawElements(GL_TRIANGLES, grid_indices_, GL_UNSIGNED_INT, nullptr); }, 1);
}

// LP_NUM_THREADS as llvmpipe reads it when the first context is made (unset:
// one rasterizer thread per CPU).
std::string lp_threads() {
  const char* v = std::getenv("LP_NUM_THREADS");
  return v ? std::string(v) : std::to_string(std::thread::hardware_concurrency()) + " (default: CPUs)";
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.empty() ? 0 : v.size() % 2 ? v[h] : (v[h - 1] + v[h]) / 2;
}

// Fill rate against quads per frame: the rate must level off (a frame's
// clear and flush amortized) and time grow with the quads (nothing dropped).
void fill_rate_sweep(LimitRig& rig, bool quick) {
  using T = LimitRig::Target;
  using S = LimitRig::Shading;
  Csv csv("shading_fill_rate", {"target", "quads", "seconds", "mpixels_per_s", "lp_threads", "load1"});
  const std::vector<std::tuple<const char*, T, S>> cases = {{"1080p 1x constant", T::image, S::constant},
                                                            {"1080p 4x MSAA constant", T::image_msaa, S::constant},
                                                            {"2048^2 depth only", T::shadow_map, S::depth_only},
                                                            {"1080p 4x MSAA PCF gathers", T::image_msaa, S::pcf}};
  for (const auto& [name, target, shading] : cases)
    for (int q : quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 2, 4, 8, 16}) {
      const auto t = loom::bench::time_median(
          [&, target = target, shading = shading] { rig.quads(target, shading, q); }, quick ? 3 : 5);
      csv.row({std::string(name), static_cast<long long>(q), t.median, q * rig.pixels(target) / t.median * 1e-6,
               lp_threads(), loom::bench::load_average()});
    }
  csv.save();
  loom::bench::plot(
      csv, {"quads", "mpixels_per_s", "target",
            "llvmpipe fill rate vs full-screen quads per frame (" + lp_threads() + " threads)", true, true, ""});
}

}  // namespace

void llvmpipe_limits(bool quick, const RenderFrame& render) {
  using T = LimitRig::Target;
  using S = LimitRig::Shading;
  LimitRig rig(render);
  fill_rate_sweep(rig, quick);

  // Render's frame and the limit runs alternate round by round; the quad runs
  // draw `q` quads per frame so that clear and flush weigh little in the rate.
  const int q = 16, runs = quick ? 3 : 7;
  std::vector<double> shadow_s, draw_s, readback_s, upload_s;
  const auto t = loom::bench::time_alternating(
      runs, {[&] {
               RenderTimings r;
               render.run(r);
               shadow_s.push_back(r.shadows);
               draw_s.push_back(r.draw);
               readback_s.push_back(r.readback);
               upload_s.push_back(r.upload);
             },
             [&] { rig.quads(T::image, S::constant, q); }, [&] { rig.quads(T::image_msaa, S::constant, q); },
             [&] { rig.quads(T::shadow_map, S::depth_only, q); }, [&] { rig.quads(T::image_msaa, S::pcf, q); },
             [&] { rig.grid(T::shadow_map, S::depth_only); }, [&] { rig.grid(T::image_msaa, S::constant); },
             [&] { rig.quads(T::shadow_map, S::depth_only, 0); }, [&] { rig.quads(T::image_msaa, S::constant, 0); }});
  const double load = loom::bench::load_average();
  const double px = rig.pixels(T::image), texels = rig.pixels(T::shadow_map);
  const double fill1 = q * px / t[1].wall, fill4 = q * px / t[2].wall, depth = q * texels / t[3].wall,
               pcf4 = q * px / t[4].wall;
  const double frame = t[0].wall, shadow = median(shadow_s), draw = median(draw_s);
  const double tris = static_cast<double>(rig.grid_triangles());

  Csv csv("shading_limits",
          {"measure", "seconds", "cpu_seconds", "rate", "rate_unit", "fraction_of_limit", "lp_threads", "load1"});
  auto row = [&](const std::string& what, double s, double cpu, double rate, const std::string& unit, double fraction) {
    csv.row({what, s, cpu, rate, unit, fraction, lp_threads(), load});
  };
  const std::string Q = " (" + std::to_string(q) + " full-screen quads)";
  row("Render frame (wall; passes below)", frame, t[0].cpu, 1 / frame, "frames/s", 0);
  row("Render upload", median(upload_s), 0, 0, "", 0);
  row("Render shadow pass", shadow, 0, 0, "", 0);
  row("Render main pass (clear, draw, shade)", draw, 0, 0, "", 0);
  row("Render resolve + readback", median(readback_s), 0, 0, "", 0);
  row("fill 1080p 1x, constant colour, no depth test" + Q, t[1].wall, t[1].cpu, fill1 * 1e-6, "Mpixel/s", 0);
  row("fill 1080p 4x MSAA, constant colour, no depth test" + Q, t[2].wall, t[2].cpu, fill4 * 1e-6, "Mpixel/s", 0);
  row("depth-only fill 2048^2, GL_LESS" + Q, t[3].wall, t[3].cpu, depth * 1e-6, "Mtexel/s", 0);
  row("fill 1080p 4x MSAA + 5x5 PCF gathers" + Q, t[4].wall, t[4].cpu, pcf4 * 1e-6, "Mpixel/s", 0);
  const std::string G = std::to_string(rig.grid_triangles()) + " 2-pixel triangles, clear included";
  row("setup: " + G + ", depth only 2048^2", t[5].wall, t[5].cpu, tris / t[5].wall * 1e-6, "Mtriangle/s", 0);
  row("setup: " + G + ", 1080p 4x MSAA", t[6].wall, t[6].cpu, tris / t[6].wall * 1e-6, "Mtriangle/s", 0);
  row("clear 2048^2 depth (frame of no draws)", t[7].wall, t[7].cpu, texels / t[7].wall * 1e-6, "Mtexel/s", 0);
  row("clear 1080p 4x MSAA colour + depth (frame of no draws)", t[8].wall, t[8].cpu, px / t[8].wall * 1e-6, "Mpixel/s",
      0);
  // The frame at llvmpipe's rates: every pixel (4x MSAA) and map texel once
  // at the raw fill rates; then with the PCF gathers on every pixel; then
  // with each pass's clear and triangles added (the grid runs). The resolve
  // and readback are not fill: they stay outside every limit.
  const double raw = px / fill4 + texels / depth;
  const double with_pcf = px / pcf4 + texels / depth;
  const double shadow_limit = t[5].wall + texels / depth, main_limit = t[6].wall + px / pcf4;
  row("limit: raw fill (1080p 4x + 2048^2 depth) / Render frame", raw, 0, 0, "", raw / frame);
  row("limit: fill + PCF gathers / Render frame", with_pcf, 0, 0, "", with_pcf / frame);
  row("limit: + clears and triangles / Render frame", shadow_limit + main_limit, 0, 0, "",
      (shadow_limit + main_limit) / frame);
  row("limit: + clears and triangles / Render shadow + main pass", shadow_limit + main_limit, 0, 0, "",
      (shadow_limit + main_limit) / (shadow + draw));
  row("limit: shadow pass (triangles + depth fill) / Render shadow pass", shadow_limit, 0, 0, "",
      shadow_limit / shadow);
  row("limit: main pass (triangles + fill + PCF) / Render main pass", main_limit, 0, 0, "", main_limit / draw);
  csv.save();
}

}  // namespace loom::shading
