#include "rasterizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "closed_surface.hpp"
#include "gl_context.hpp"
#include "gl_program.hpp"
#include "gpu_scene.hpp"
#include "irradiance_sh.hpp"
#include "loom/error.hpp"
#include "shader_sources.hpp"
#include "shadow_pass.hpp"
#include "view_math.hpp"

namespace loom::shading {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
double process_cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Blinn-Phong exponent from the perceptual roughness: alpha = roughness²,
// s = 2 / alpha² - 2 (Walter et al. 2007's Beckmann/Phong correspondence).
double shininess(double roughness) {
  const double a = std::max(roughness * roughness, 1e-3);
  return std::clamp(2 / (a * a) - 2, 1.0, 1e4);
}

Eigen::Vector3d ambient_of(const Environment& env) {
  if (!env.map || env.map->empty()) return env.color * env.intensity;
  const cv::Scalar mean = cv::mean(env.map->pixels);
  const int ch = env.map->channels();
  if (ch < 3) return Eigen::Vector3d::Constant(mean[0] * env.intensity);
  return Eigen::Vector3d(mean[0], mean[1], mean[2]) * env.intensity;
}

// GL's rows go bottom-up: the image top row first, as float, with no NaN or
// infinity (a degenerate frame could make one), in one parallel pass. Rows
// widen by convertTo: OpenCV picks F16C for half floats at run time (exact,
// as any half-to-float conversion: all 65536 halves give the same floats as
// cv::float16_t's portable bit arithmetic, which made this pass 3x slower).
cv::Mat flipped_finite(const cv::Mat& raw) {
  cv::Mat out(raw.size(), CV_32FC4);
  const int H = raw.rows;
  const std::size_t n = static_cast<std::size_t>(raw.cols) * 4;
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      cv::Mat row = out.row(y);
      raw.row(H - 1 - y).convertTo(row, CV_32F);
      float* v = row.ptr<float>();
      for (std::size_t i = 0; i < n; ++i) v[i] = std::isnan(v[i]) ? 0.0f : std::clamp(v[i], -1e30f, 1e30f);
    }
  });
  return out;
}

}  // namespace

// The image's attachments: color, normal, position (+ depth), shadow. Color
// is half float: 11 significant bits, 1/2048 relative, far below 1/255.
constexpr GLenum formats[4] = {GL_RGBA16F, GL_RGBA16F, GL_RGBA32F, GL_RGBA16F};

struct Rasterizer::State {
  GlContext context;
  double context_seconds = 0, compile_seconds = 0;
  int max_samples = 1;
  float line_width_range[2] = {1, 1};
  GLuint empty_vao = 0;
  std::unique_ptr<GpuCache> gpu_cache;  // core profile: a draw needs a vertex array, even one without attributes
  std::unique_ptr<GlProgram> depth, depth_only, depth_tess, sphere_depth, line, background;
  // The image's framebuffers, kept while the size, samples and attachments
  // stay the same: llvmpipe allocates (and the kernel zeroes) every sample in
  // host memory, ~100 MB at 1080p with 4x MSAA, a cost worth paying once.
  struct Targets {
    int width = 0, height = 0, samples = 0, attachments = 0;
    GLuint msaa = 0, resolve = 0, ms_tex[5] = {}, rs_tex[4] = {};
  } targets;
  void release_targets();
  Targets& image_targets(int width, int height, int samples, int attachments);
  // The environment map on the GPU and its SH irradiance, computed once per
  // map and rotation (the map is held, so its address stays a valid key).
  struct EnvironmentMap {
    std::shared_ptr<const Image> map;
    double rotation = 0;
    GLuint texture = 0;
    int levels = 0;
    Sh9 irradiance;
  } environment;
  // The cached map for this environment, or null if it has none.
  const EnvironmentMap* environment_map(const Environment& env);
  // Lighting programs by kind and #defines, compiled when first needed.
  std::map<std::string, std::unique_ptr<GlProgram>> lit;

  const GlApi& gl() const { return context.gl(); }
  enum class Lit { mesh, mesh_tess, sphere };
  GlProgram& lit_program(Lit kind, const std::string& defines);

  // What every draw of one render shares.
  struct Frame {
    const Scene& scene;
    const RenderOptions& options;
    Camera camera;
    Eigen::Matrix4d view, proj, view_proj;
    Eigen::Vector3d ambient;
    const EnvironmentMap* env;
    const std::vector<ShadowMap>& maps;
    std::string lighting;  // lighting_defines of this frame
  };
  // The steps of a render, in order.
  const Targets& clear_targets(const Frame& f);
  void draw_background(const Frame& f);
  void draw_object(const Frame& f, const GpuObject& o);
  void draw_wireframe(const Frame& f, const GpuScene& gpu);
  RenderImages read_back(const Targets& fb);

  // Deletes the GL objects with the context current (a constructor that
  // throws half way leaves the same to clean up).
  ~State();
};

Rasterizer::State::~State() {
  try {
    GlContext::Current current(context);
    release_targets();
    gpu_cache.reset();
    if (environment.texture) gl().DeleteTextures(1, &environment.texture);
    lit.clear();
    depth.reset();
    depth_only.reset();
    depth_tess.reset();
    sphere_depth.reset();
    background.reset();
    line.reset();
    if (empty_vao) gl().DeleteVertexArrays(1, &empty_vao);
  } catch (const Error&) {
    // The context cannot be made current: destroying it frees its objects.
  }
}

const Rasterizer::State::EnvironmentMap* Rasterizer::State::environment_map(const Environment& env) {
  if (!env.map || env.map->empty()) return nullptr;
  EnvironmentMap& e = environment;
  if (e.texture && e.map == env.map && e.rotation == env.rotation) return &e;
  if (e.texture) gl().DeleteTextures(1, &e.texture);
  e = EnvironmentMap{};
  cv::Mat px;
  env.map->pixels.convertTo(px, CV_32F);
  if (px.channels() == 1) cv::cvtColor(px, px, cv::COLOR_GRAY2RGB);
  if (px.channels() == 4) cv::cvtColor(px, px, cv::COLOR_RGBA2RGB);
  if (px.channels() != 3) throw Error("environment map needs 1, 3 or 4 channels");
  if (!px.isContinuous()) px = px.clone();
  const GlApi& gl = this->gl();
  e.levels = 1;
  for (int n = std::max(px.cols, px.rows); n > 1; n /= 2) ++e.levels;
  gl.CreateTextures(GL_TEXTURE_2D, 1, &e.texture);
  gl.TextureStorage2D(e.texture, e.levels, GL_RGB32F, px.cols, px.rows);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TextureSubImage2D(e.texture, 0, 0, 0, px.cols, px.rows, GL_RGB, GL_FLOAT, px.data);
  gl.GenerateTextureMipmap(e.texture);
  gl.TextureParameteri(e.texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  gl.TextureParameteri(e.texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl.TextureParameteri(e.texture, GL_TEXTURE_WRAP_S, GL_REPEAT);
  gl.TextureParameteri(e.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.check("uploading the environment map");
  e.map = env.map;
  e.rotation = env.rotation;
  e.irradiance = sh9_irradiance_coefficients(sh9_project(*env.map, env.rotation));
  return &e;
}

void Rasterizer::State::release_targets() {
  if (!targets.msaa) return;
  gl().DeleteFramebuffers(1, &targets.msaa);
  gl().DeleteFramebuffers(1, &targets.resolve);
  gl().DeleteTextures(5, targets.ms_tex);
  gl().DeleteTextures(4, targets.rs_tex);
  targets = Targets{};
}

Rasterizer::State::Targets& Rasterizer::State::image_targets(int W, int H, int samples, int attachments) {
  Targets& t = targets;
  if (t.msaa && t.width == W && t.height == H && t.samples == samples && t.attachments == attachments) return t;
  release_targets();
  const GlApi& gl = this->gl();
  t.width = W;
  t.height = H;
  t.samples = samples;
  t.attachments = attachments;
  gl.CreateFramebuffers(1, &t.msaa);
  gl.CreateFramebuffers(1, &t.resolve);
  GLenum draw_buffers[4];
  for (int a = 0; a < attachments; ++a) {
    gl.CreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &t.ms_tex[a]);
    gl.TextureStorage2DMultisample(t.ms_tex[a], samples, formats[a], W, H, GL_TRUE);
    gl.NamedFramebufferTexture(t.msaa, GL_COLOR_ATTACHMENT0 + a, t.ms_tex[a], 0);
    gl.CreateTextures(GL_TEXTURE_2D, 1, &t.rs_tex[a]);
    gl.TextureStorage2D(t.rs_tex[a], 1, formats[a], W, H);
    gl.NamedFramebufferTexture(t.resolve, GL_COLOR_ATTACHMENT0 + a, t.rs_tex[a], 0);
    draw_buffers[a] = GL_COLOR_ATTACHMENT0 + a;
  }
  gl.CreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &t.ms_tex[4]);
  gl.TextureStorage2DMultisample(t.ms_tex[4], samples, GL_DEPTH_COMPONENT32F, W, H, GL_TRUE);
  gl.NamedFramebufferTexture(t.msaa, GL_DEPTH_ATTACHMENT, t.ms_tex[4], 0);
  gl.NamedFramebufferDrawBuffers(t.msaa, attachments, draw_buffers);
  if (gl.CheckNamedFramebufferStatus(t.msaa, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    release_targets();
    throw Error("the render framebuffer is incomplete (" + std::to_string(W) + "x" + std::to_string(H) + ", " +
                std::to_string(samples) + " samples)");
  }
  return t;
}

GlProgram& Rasterizer::State::lit_program(Lit kind, const std::string& defines) {
  const std::string key = std::to_string(static_cast<int>(kind)) + defines;
  auto it = lit.find(key);
  if (it != lit.end()) return *it->second;
  // A scene that keeps changing its lights could compile without end: start over.
  if (lit.size() >= 64) lit.clear();
  using namespace glsl;
  std::unique_ptr<GlProgram> p;
  if (kind == Lit::sphere) {
    const std::string fragment = sphere_fragment(defines);
    p = std::make_unique<GlProgram>(gl(), "sphere impostors", std::vector<std::pair<GLenum, const char*>>{
        {GL_VERTEX_SHADER, sphere_vertex}, {GL_GEOMETRY_SHADER, sphere_geometry},
        {GL_FRAGMENT_SHADER, fragment.c_str()}});
  } else {
    const std::string fragment = mesh_fragment(defines);
    if (kind == Lit::mesh)
      p = std::make_unique<GlProgram>(gl(), "mesh", std::vector<std::pair<GLenum, const char*>>{
          {GL_VERTEX_SHADER, mesh_vertex}, {GL_FRAGMENT_SHADER, fragment.c_str()}});
    else
      p = std::make_unique<GlProgram>(gl(), "displaced mesh", std::vector<std::pair<GLenum, const char*>>{
          {GL_VERTEX_SHADER, mesh_vertex}, {GL_TESS_CONTROL_SHADER, mesh_tess_control},
          {GL_TESS_EVALUATION_SHADER, mesh_tess_eval}, {GL_FRAGMENT_SHADER, fragment.c_str()}});
  }
  return *lit.emplace(key, std::move(p)).first->second;
}

Rasterizer::Rasterizer() {
  const auto t0 = Clock::now();
  state_ = std::make_unique<State>();
  state_->context_seconds = since(t0);
  const auto t1 = Clock::now();
  GlContext::Current current(state_->context);
  const GlApi& gl = state_->gl();
  using namespace glsl;
  auto& s = *state_;
  s.depth_only = std::make_unique<GlProgram>(gl, "depth only", std::vector<std::pair<GLenum, const char*>>{
      {GL_VERTEX_SHADER, mesh_vertex}, {GL_FRAGMENT_SHADER, empty_fragment}});
  s.depth = std::make_unique<GlProgram>(gl, "shadow depth", std::vector<std::pair<GLenum, const char*>>{
      {GL_VERTEX_SHADER, mesh_vertex}, {GL_FRAGMENT_SHADER, depth_fragment}});
  s.depth_tess = std::make_unique<GlProgram>(gl, "displaced shadow depth", std::vector<std::pair<GLenum, const char*>>{
      {GL_VERTEX_SHADER, mesh_vertex}, {GL_TESS_CONTROL_SHADER, mesh_tess_control},
      {GL_TESS_EVALUATION_SHADER, mesh_tess_eval}, {GL_FRAGMENT_SHADER, depth_fragment}});
  const std::string sphere_depth_fragment = sphere_fragment(lighting_defines({}) + "#define DEPTH_PASS 1\n");
  s.sphere_depth = std::make_unique<GlProgram>(gl, "sphere impostor depth", std::vector<std::pair<GLenum, const char*>>{
      {GL_VERTEX_SHADER, sphere_vertex}, {GL_GEOMETRY_SHADER, sphere_geometry},
      {GL_FRAGMENT_SHADER, sphere_depth_fragment.c_str()}});
  s.line = std::make_unique<GlProgram>(gl, "lines", std::vector<std::pair<GLenum, const char*>>{
      {GL_VERTEX_SHADER, line_vertex}, {GL_FRAGMENT_SHADER, line_fragment}});
  gl.CreateVertexArrays(1, &s.empty_vao);
  s.gpu_cache = std::make_unique<GpuCache>(gl);
  gl.GetIntegerv(GL_MAX_SAMPLES, &s.max_samples);
  GLint range[2] = {1, 1};
  gl.GetIntegerv(GL_ALIASED_LINE_WIDTH_RANGE, range);
  s.line_width_range[0] = static_cast<float>(range[0]);
  s.line_width_range[1] = static_cast<float>(range[1]);
  gl.check("compiling the rasterizer's programs");
  s.compile_seconds = since(t1);
}

Rasterizer::~Rasterizer() = default;

double Rasterizer::context_seconds() const { return state_->context_seconds; }
double Rasterizer::compile_seconds() const { return state_->compile_seconds; }
int Rasterizer::max_samples() const { return state_->max_samples; }
const std::string& Rasterizer::renderer() const { return state_->context.renderer(); }

namespace {

// Light a surface of this material reflects from the environment map, mirror-like
// (the coat of plastic, F0 = base_color of a conductor); none for the others.
Eigen::Vector3d environment_reflectance(const Material& m) {
  if (m.model == Material::Model::plastic) return Eigen::Vector3d::Constant(m.specular);
  if (m.model == Material::Model::conductor) return m.specular * m.base_color;
  return Eigen::Vector3d::Zero();
}

template <class EnvironmentMap>
void set_lighting(GlProgram& p, const Scene& scene, const std::vector<ShadowMap>& maps,
                  const RenderOptions& o, const Eigen::Vector3d& eye, const Eigen::Vector3d& ambient,
                  const EnvironmentMap* env) {
  bind_sampler_units(p);
  p.set("u_eye", eye);
  p.set("u_ambient", ambient);
  if (env) {
    for (int k = 0; k < 9; ++k)
      p.set(("u_env_sh[" + std::to_string(k) + "]").c_str(), Eigen::Vector3d(env->irradiance[k] * scene.environment.intensity));
    p.set("u_env_rotation", env->rotation);
    p.set("u_env_intensity", scene.environment.intensity);
    p.set("u_env_height", static_cast<double>(env->map->height()));
    p.set("u_env_max_level", static_cast<double>(env->levels - 1));
  }
  const int n = std::min<int>(static_cast<int>(scene.lights.size()), max_lights);
  for (int i = 0; i < n; ++i) {
    const Light& l = scene.lights[i];
    const std::string k = "[" + std::to_string(i) + "]";
    p.set(("u_light_position" + k).c_str(), l.position);
    p.set(("u_light_direction" + k).c_str(), Eigen::Vector3d(l.direction.normalized()));
    p.set(("u_light_radiance" + k).c_str(), Eigen::Vector3d(l.color * l.intensity));
    p.set(("u_spot_cos_inner" + k).c_str(), std::cos(l.spot_inner));
    p.set(("u_spot_cos_outer" + k).c_str(), std::cos(std::max(l.spot_outer, l.spot_inner + 1e-4)));
  }
  p.set("u_bias", o.shadow_bias);
  p.set("u_slope_bias", o.shadow_slope_bias);
  p.set("u_light_size", o.light_size);
  // Clip to window coordinates (GL's default depth range): x, y, z in [0, 1].
  Eigen::Matrix4d clip_to_window = Eigen::Matrix4d::Identity();
  clip_to_window.topLeftCorner<3, 3>() *= 0.5;
  clip_to_window.topRightCorner<3, 1>().setConstant(0.5);
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const ShadowView& v = maps[m].view;
    const std::string k = "[" + std::to_string(m) + "]";
    p.set(("u_shadow_matrix" + k).c_str(), Eigen::Matrix4d(clip_to_window * v.projection * v.view));
    p.set(("u_shadow_origin" + k).c_str(), v.origin);
    p.set(("u_shadow_axis" + k).c_str(), v.axis);
    p.set(("u_shadow_texel" + k).c_str(), v.texel);
    p.set(("u_shadow_resolution" + k).c_str(), o.shadow_resolution);
    p.set(("u_shadow_depth_range" + k).c_str(),
          v.ortho ? Eigen::Vector2d(v.near_plane, v.far_plane - v.near_plane) : Eigen::Vector2d(0, 1));
  }
}

// What the lighting programs are compiled for: each light's kind and shadow
// slot, the shadow filter, the environment.
LightingVariant lighting_variant(const Scene& scene, const std::vector<ShadowMap>& maps, const RenderOptions& o,
                                 bool environment_map) {
  LightingVariant v;
  v.environment_map = environment_map;
  const int n = std::min<int>(static_cast<int>(scene.lights.size()), max_lights);
  for (int i = 0; i < n; ++i) {
    const Light& l = scene.lights[i];
    int slot = -1;
    for (std::size_t m = 0; m < maps.size(); ++m)
      if (maps[m].light == i) slot = static_cast<int>(m);
    v.lights.emplace_back(l.kind, slot);
  }
  if (!maps.empty()) v.shadow_filter = o.shadows;
  v.pcf_size = o.pcf_size;
  return v;
}

void check_options(const RenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
    throw Error("image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                " is outside 1..16384");
  // llvmpipe allocates every sample in host memory: refuse what cannot fit
  // (2^28 samples is 4 GiB of RGBA16F color alone, before depth).
  if (static_cast<double>(options.width) * options.height * std::max(options.samples, 1) > double(1 << 28))
    throw Error("image of " + std::to_string(options.width) + "x" + std::to_string(options.height) + " with " +
                std::to_string(options.samples) + " samples per pixel is too large: lower the size or samples");
  if (options.shadow_resolution < 16 || options.shadow_resolution > 16384)
    throw Error("shadow_resolution must be in 16..16384");
  if (options.pcf_size < 1 || options.pcf_size > 15) throw Error("pcf_size must be in 1..15");
}

// The objects in the order they are drawn: meshes nearest first (by the
// distance from the eye to their bounds' center), then points and lines in
// the scene's order, so that fewer hidden fragments are shaded before the
// nearer surface arrives (measured on the target frame, sphere before floor:
// main pass 4 % and 15 % less CPU time in two sets of 6 alternating rounds,
// loads 5-6). Only fragments at exactly equal depth can fall to another object.
std::vector<const GpuObject*> nearest_first(const GpuScene& gpu, const Eigen::Vector3d& eye) {
  std::vector<std::pair<double, const GpuObject*>> keyed;
  for (const GpuObject& o : gpu.objects()) {
    if (o.count == 0) continue;
    double key = std::numeric_limits<double>::infinity();
    if (o.kind == GpuObject::Kind::mesh && !o.bounds.isEmpty())
      key = ((o.source->transform * o.bounds.center().homogeneous()).hnormalized() - eye).norm();
    keyed.emplace_back(key, &o);
  }
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<const GpuObject*> order;
  for (const auto& [key, o] : keyed) order.push_back(o);
  return order;
}

// The GL state every render starts from.
void set_draw_state(const GlApi& gl) {
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  gl.Disable(GL_CULL_FACE);
  gl.Disable(GL_BLEND);
  gl.Enable(GL_PROGRAM_POINT_SIZE);
  gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  gl.PatchParameteri(GL_PATCH_VERTICES, 3);
}

}  // namespace

// The image's MSAA framebuffer (color + optional normal, position, shadow),
// bound and cleared: color to the ambient, position to the far plane, shadow to lit.
const Rasterizer::State::Targets& Rasterizer::State::clear_targets(const Frame& f) {
  const GlApi& gl = this->gl();
  const RenderOptions& o = f.options;
  const int samples = std::clamp(o.samples, 1, max_samples);
  const int attachments = o.aux ? 4 : 1;
  const Targets& fb = image_targets(o.width, o.height, samples, attachments);
  GLenum draw_buffers[4];
  for (int a = 0; a < attachments; ++a) draw_buffers[a] = GL_COLOR_ATTACHMENT0 + a;
  gl.NamedFramebufferDrawBuffers(fb.msaa, attachments, draw_buffers);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fb.msaa);
  gl.Viewport(0, 0, o.width, o.height);
  const Eigen::Vector3d& bg = f.ambient;
  const float clear_color[4] = {float(bg.x()), float(bg.y()), float(bg.z()), 0};
  const float clear_zero[4] = {0, 0, 0, 0};
  const float clear_position[4] = {0, 0, 0, float(f.camera.far_plane)};
  const float clear_shadow[4] = {1, 0, 0, 0};
  const float one = 1;
  gl.ClearBufferfv(GL_COLOR, 0, clear_color);
  if (o.aux) {
    gl.ClearBufferfv(GL_COLOR, 1, clear_zero);
    gl.ClearBufferfv(GL_COLOR, 2, clear_position);
    gl.ClearBufferfv(GL_COLOR, 3, clear_shadow);
  }
  gl.ClearBufferfv(GL_DEPTH, 0, &one);
  return fb;
}

// The environment map behind the scene, at the far plane, no depth written.
void Rasterizer::State::draw_background(const Frame& f) {
  if (!f.env) return;
  const GlApi& gl = this->gl();
  if (!background) {
    const std::string fragment = glsl::background_fragment();
    background = std::make_unique<GlProgram>(
        gl, "environment background",
        std::vector<std::pair<GLenum, const char*>>{{GL_VERTEX_SHADER, glsl::background_vertex},
                                                    {GL_FRAGMENT_SHADER, fragment.c_str()}});
  }
  GlProgram& p = *background;
  p.use();
  set_lighting(p, f.scene, {}, f.options, f.camera.eye, f.ambient, f.env);
  p.set("u_inverse_view_proj", Eigen::Matrix4d(f.view_proj.inverse()));
  p.set("u_far", f.camera.far_plane);
  gl.DepthMask(GL_FALSE);
  gl.Disable(GL_DEPTH_TEST);
  gl.BindVertexArray(empty_vao);
  gl.DrawArrays(GL_TRIANGLES, 0, 3);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthMask(GL_TRUE);
}

// One object: points as lit sphere impostors, lines unlit, meshes lit with
// their maps (through the tessellation programs when displaced).
void Rasterizer::State::draw_object(const Frame& f, const GpuObject& o) {
  const GlApi& gl = this->gl();
  const RenderOptions& options = f.options;
  const Material& mat = o.source->material;
  gl.BindVertexArray(o.vao);
  if (o.kind == GpuObject::Kind::lines) {
    GlProgram& p = *line;
    p.use();
    p.set("u_model", o.source->transform);
    p.set("u_view_proj", f.view_proj);
    p.set("u_view", f.view);
    p.set("u_uniform_color", false);
    gl.LineWidth(std::clamp(static_cast<float>(options.line_width), line_width_range[0], line_width_range[1]));
    gl.DrawElements(GL_LINES, o.count, GL_UNSIGNED_INT, nullptr);
    return;
  }
  const bool points = o.kind == GpuObject::Kind::points;
  const bool tess = !points && displaced(o, options.tessellation);
  const std::string defines =
      points ? f.lighting + "#define DEPTH_PASS 0\n"
             : f.lighting + "#define HAS_BASE_MAP " + (o.base_map ? "1" : "0") + "\n#define HAS_NORMAL_MAP " +
                   (o.normal_map ? "1" : "0") + "\n#define HAS_DISPLACEMENT " + (tess ? "1" : "0") +
                   "\n#define HAS_VERTEX_COLOR " + (o.source->mesh->has_colors() ? "1" : "0") + "\n";
  GlProgram& p = lit_program(points ? Lit::sphere : tess ? Lit::mesh_tess : Lit::mesh, defines);
  p.use();
  set_lighting(p, f.scene, f.maps, options, f.camera.eye, f.ambient, f.env);
  p.set("u_env_reflectance", environment_reflectance(mat));
  p.set("u_model", o.source->transform);
  if (points) {
    p.set("u_radius_scale", o.source->points->has_radius() ? 1.0 : options.point_radius);
    p.set("u_view", f.view);
    p.set("u_proj", f.proj);
    p.set("u_ortho", f.camera.projection == Camera::Projection::orthographic);
    p.set("u_inverse_view_proj", Eigen::Matrix4d(f.view_proj.inverse()));
    p.set("u_viewport", Eigen::Vector2d(options.width, options.height));
    p.set("u_specular", mat.specular);
    p.set("u_shininess", shininess(mat.roughness));
    gl.DrawArrays(GL_POINTS, 0, o.count);
    return;
  }
  p.set("u_normal_matrix", normal_matrix(o.source->transform));
  p.set("u_view_proj", f.view_proj);
  p.set("u_view", f.view);
  p.set("u_base_color", mat.base_color);
  p.set("u_emission", mat.emission);
  p.set("u_specular", mat.specular);
  p.set("u_shininess", shininess(mat.roughness));
  p.set("u_displacement_scale", mat.displacement_scale);
  if (o.base_map) gl.BindTextureUnit(unit_base, o.base_map);
  if (o.normal_map) gl.BindTextureUnit(unit_normal, o.normal_map);
  if (o.displacement_map) gl.BindTextureUnit(unit_displacement, o.displacement_map);
  if (tess) {
    p.set("u_tess_level", static_cast<double>(options.tessellation));
    draw_patches(gl, o.count, options.tessellation);
  } else {
    // A closed mesh's hidden side is skipped before llvmpipe sets it up (closed_surface.hpp).
    const GLenum hidden = hidden_side(o.closed, o.bounds, o.source->transform, f.view, f.camera.near_plane);
    if (hidden) {
      gl.Enable(GL_CULL_FACE);
      gl.CullFace(hidden);
    }
    draw_triangles(gl, o.count, options.check_cancelled);
    gl.Disable(GL_CULL_FACE);
  }
}

// Mesh edges over the shading (the fill was pushed back by a polygon offset).
void Rasterizer::State::draw_wireframe(const Frame& f, const GpuScene& gpu) {
  const GlApi& gl = this->gl();
  GlProgram& p = *line;
  p.use();
  p.set("u_view_proj", f.view_proj);
  p.set("u_view", f.view);
  p.set("u_uniform_color", true);
  p.set("u_color", f.options.wireframe_color);
  gl.PolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  gl.DepthFunc(GL_LEQUAL);
  gl.LineWidth(std::clamp(static_cast<float>(f.options.line_width), line_width_range[0], line_width_range[1]));
  for (const GpuObject& o : gpu.objects()) {
    if (o.kind != GpuObject::Kind::mesh || o.count == 0) continue;
    p.set("u_model", o.source->transform);
    gl.BindVertexArray(o.vao);
    gl.DrawElements(GL_TRIANGLES, o.count, GL_UNSIGNED_INT, nullptr);
  }
  gl.PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  gl.DepthFunc(GL_LESS);
}

// Resolves the samples and reads each attachment back (GL's rows go bottom-up).
RenderImages Rasterizer::State::read_back(const Targets& fb) {
  const GlApi& gl = this->gl();
  const int W = fb.width, H = fb.height;
  RenderImages images;
  cv::Mat* images_of[4] = {&images.color, &images.normal, &images.position, &images.shadow};
  for (int a = 0; a < fb.attachments; ++a) {
    const GLenum attachment = GL_COLOR_ATTACHMENT0 + a;
    gl.NamedFramebufferReadBuffer(fb.msaa, attachment);
    gl.NamedFramebufferDrawBuffers(fb.resolve, 1, &attachment);
    gl.BlitNamedFramebuffer(fb.msaa, fb.resolve, 0, 0, W, H, 0, 0, W, H, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, fb.resolve);
    gl.NamedFramebufferReadBuffer(fb.resolve, attachment);
    // Half-float attachments are read as stored (half the bytes, no
    // conversion on this thread) and widened in the parallel flip.
    const bool half = formats[a] == GL_RGBA16F;
    cv::Mat raw(H, W, half ? CV_16FC4 : CV_32FC4);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadPixels(0, 0, W, H, GL_RGBA, half ? GL_HALF_FLOAT : GL_FLOAT, raw.data);
    cv::Mat rgba = flipped_finite(raw);
    if (a == 1) cv::cvtColor(rgba, rgba, cv::COLOR_RGBA2RGB);
    if (a == 3) cv::extractChannel(rgba, rgba, 0);
    *images_of[a] = rgba;
  }
  gl.check("reading the image back");
  return images;
}

RenderImages Rasterizer::render(const Scene& scene, const RenderOptions& options, RenderTimings* timings) {
  require_valid(scene, "scene");
  check_options(options);
  RenderTimings local;
  RenderTimings& time = timings ? *timings : local;
  State& s = *state_;
  GlContext::Current current(s.context);
  const GlApi& gl = s.gl();
  auto t = Clock::now();
  double c = process_cpu_seconds();

  const auto check_cancelled = [&options] {
    if (options.check_cancelled) options.check_cancelled();
  };
  GpuScene gpu(gl, scene, *s.gpu_cache, options.check_cancelled);
  const double aspect = static_cast<double>(options.width) / options.height;
  const Camera camera = scene.camera ? *scene.camera : framing_camera(scene, aspect);
  Eigen::Matrix4d view, proj;
  camera_matrices(camera, aspect, view, proj);
  Eigen::AlignedBox3d box = bounds(scene);
  if (box.isEmpty()) box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  set_draw_state(gl);
  gl.check("uploading the scene");
  time.upload = since(t);
  time.upload_cpu = process_cpu_seconds() - c;

  t = Clock::now();
  c = process_cpu_seconds();
  ShadowMaps shadows(gl);
  render_shadow_maps(gl, {*s.depth, *s.depth_only, *s.depth_tess, *s.sphere_depth}, gpu, scene, box, options, shadows);
  gl.Finish();
  check_cancelled();
  time.shadows = since(t);
  time.shadows_cpu = process_cpu_seconds() - c;

  t = Clock::now();
  c = process_cpu_seconds();
  const State::EnvironmentMap* env = s.environment_map(scene.environment);
  if (env) gl.BindTextureUnit(unit_environment, env->texture);
  const State::Frame frame{scene,
                           options,
                           camera,
                           view,
                           proj,
                           proj * view,
                           ambient_of(scene.environment),
                           env,
                           shadows.maps,
                           lighting_defines(lighting_variant(scene, shadows.maps, options, env != nullptr))};
  const State::Targets& fb = s.clear_targets(frame);
  s.draw_background(frame);
  if (options.wireframe) {
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(1, 1);
  }
  for (const GpuObject* o : nearest_first(gpu, camera.eye)) s.draw_object(frame, *o);
  gl.Disable(GL_POLYGON_OFFSET_FILL);
  if (options.wireframe) s.draw_wireframe(frame, gpu);
  gl.check("drawing the scene");
  gl.Finish();
  check_cancelled();
  time.draw = since(t);
  time.draw_cpu = process_cpu_seconds() - c;

  t = Clock::now();
  c = process_cpu_seconds();
  RenderImages images = s.read_back(fb);
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.BindVertexArray(0);
  gl.UseProgram(0);
  s.gpu_cache->release_unused();
  for (GLuint u = 0; u < texture_units_used; ++u) gl.BindTextureUnit(u, 0);
  time.readback = since(t);
  time.readback_cpu = process_cpu_seconds() - c;
  return images;
}

}  // namespace loom::shading
