#include "shadow_pass.hpp"

#include <algorithm>
#include <string>

#include "loom/error.hpp"
#include "shader_sources.hpp"

namespace loom::shading {

ShadowMaps::~ShadowMaps() {
  for (ShadowMap& m : maps) {
    gl_.DeleteFramebuffers(1, &m.fbo);
    gl_.DeleteTextures(1, &m.color);
    gl_.DeleteTextures(1, &m.depth);
  }
}

namespace {

// The map's textures and framebuffer at R x R texels.
void allocate(const GlApi& gl, ShadowMap& m, int R) {
  gl.CreateFramebuffers(1, &m.fbo);
  if (m.view.ortho) {
    // Orthographic: the depth buffer is already linear along the light,
    // depth01 = (d - near) / (far - near); it is the map (no color pass).
    // Past its edge the border, depth 1, is the far plane: beyond every
    // receiver, lit.
    gl.CreateTextures(GL_TEXTURE_2D, 1, &m.color);
    gl.TextureStorage2D(m.color, 1, GL_DEPTH_COMPONENT32F, R, R);
    const float far_border[4] = {1, 1, 1, 1};
    gl.TextureParameterfv(m.color, GL_TEXTURE_BORDER_COLOR, far_border);
    for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T}) gl.TextureParameteri(m.color, p, GL_CLAMP_TO_BORDER);
    for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) gl.TextureParameteri(m.color, p, GL_NEAREST);
    gl.NamedFramebufferTexture(m.fbo, GL_DEPTH_ATTACHMENT, m.color, 0);
    return;
  }
  gl.CreateTextures(m.view.cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, 1, &m.color);
  gl.TextureStorage2D(m.color, 1, GL_R32F, R, R);
  for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) gl.TextureParameteri(m.color, p, GL_NEAREST);
  // Past a 2D map's edge nothing casts a shadow: the border is "infinitely far".
  const float far_border[4] = {1e30f, 1e30f, 1e30f, 1e30f};
  gl.TextureParameterfv(m.color, GL_TEXTURE_BORDER_COLOR, far_border);
  for (GLenum p : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    gl.TextureParameteri(m.color, p, m.view.cube ? GL_CLAMP_TO_EDGE : GL_CLAMP_TO_BORDER);
  gl.CreateTextures(GL_TEXTURE_2D, 1, &m.depth);
  gl.TextureStorage2D(m.depth, 1, GL_DEPTH_COMPONENT32F, R, R);
  gl.NamedFramebufferTexture(m.fbo, GL_DEPTH_ATTACHMENT, m.depth, 0);
}

// The shadow casters' depth metric seen through `light_view` (one face of a cube map).
void draw_casters(const GlApi& gl, const DepthPrograms& programs, const GpuScene& gpu, const ShadowMap& m,
                  const Eigen::Matrix4d& light_view, const RenderOptions& options) {
  const int R = options.shadow_resolution;
  const Eigen::Matrix4d lvp = m.view.projection * light_view;
  for (const GpuObject& o : gpu.objects()) {
    if (!o.source->casts_shadow || o.kind == GpuObject::Kind::lines || o.count == 0) continue;
    if (o.kind == GpuObject::Kind::points) {
      GlProgram& p = programs.spheres;
      p.use();
      bind_sampler_units(p);
      p.set("u_model", o.source->transform);
      p.set("u_radius_scale", o.source->points->has_radius() ? 1.0 : options.point_radius);
      p.set("u_view", light_view);
      p.set("u_proj", m.view.projection);
      p.set("u_ortho", m.view.ortho);
      p.set("u_inverse_view_proj", Eigen::Matrix4d(lvp.inverse()));
      p.set("u_viewport", Eigen::Vector2d(R, R));
      p.set("u_depth_origin", m.view.origin);
      p.set("u_depth_axis", m.view.axis);
      p.set("u_depth_radial", !m.view.ortho);
      gl.BindVertexArray(o.vao);
      gl.DrawArrays(GL_POINTS, 0, o.count);
      continue;
    }
    const bool tess = displaced(o, options.tessellation);
    GlProgram& p = tess ? programs.tessellated : m.view.ortho ? programs.depth_only : programs.mesh;
    p.use();
    bind_sampler_units(p);
    p.set("u_model", o.source->transform);
    p.set("u_normal_matrix", normal_matrix(o.source->transform));
    p.set("u_view_proj", lvp);
    p.set("u_depth_origin", m.view.origin);
    p.set("u_depth_axis", m.view.axis);
    p.set("u_depth_radial", !m.view.ortho);
    gl.BindVertexArray(o.vao);
    if (tess) {
      p.set("u_tess_level", static_cast<double>(options.tessellation));
      p.set("u_displacement_scale", o.source->material.displacement_scale);
      gl.BindTextureUnit(unit_displacement, o.displacement_map);
      draw_patches(gl, o.count, options.tessellation);
    } else {
      draw_triangles(gl, o.count, options.check_cancelled);
    }
  }
}

}  // namespace

void render_shadow_maps(const GlApi& gl, const DepthPrograms& programs, const GpuScene& gpu, const Scene& scene,
                        const Eigen::AlignedBox3d& box, const RenderOptions& options, ShadowMaps& out) {
  std::vector<ShadowMap>& maps = out.maps;
  const int light_count = std::min<int>(static_cast<int>(scene.lights.size()), max_lights);
  if (options.shadows != ShadowFilter::off)
    for (int i = 0; i < light_count && static_cast<int>(maps.size()) < max_shadows; ++i) {
      if (!scene.lights[i].casts_shadow) continue;
      ShadowMap m;
      m.light = i;
      m.view = shadow_view(scene.lights[i], box, options.shadow_resolution);
      maps.push_back(m);
    }
  const int R = options.shadow_resolution;
  for (std::size_t mi = 0; mi < maps.size(); ++mi) {
    ShadowMap& m = maps[mi];
    allocate(gl, m, R);
    gl.BindFramebuffer(GL_FRAMEBUFFER, m.fbo);
    gl.Viewport(0, 0, R, R);
    const int faces = m.view.cube ? 6 : 1;
    for (int f = 0; f < faces; ++f) {
      if (m.view.cube)
        gl.NamedFramebufferTextureLayer(m.fbo, GL_COLOR_ATTACHMENT0, m.color, 0, f);
      else if (!m.view.ortho)
        gl.NamedFramebufferTexture(m.fbo, GL_COLOR_ATTACHMENT0, m.color, 0);
      const GLenum attachment = m.view.ortho ? GL_NONE : GL_COLOR_ATTACHMENT0;
      gl.NamedFramebufferDrawBuffers(m.fbo, 1, &attachment);
      if (gl.CheckNamedFramebufferStatus(m.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("the shadow map framebuffer is incomplete (resolution " + std::to_string(R) + ")");
      const float far_value[4] = {1e30f, 1e30f, 1e30f, 1e30f};
      const float one = 1;
      if (!m.view.ortho) gl.ClearBufferfv(GL_COLOR, 0, far_value);
      gl.ClearBufferfv(GL_DEPTH, 0, &one);
      draw_casters(gl, programs, gpu, m, m.view.cube ? m.view.faces[f] : m.view.view, options);
    }
    gl.BindTextureUnit(m.view.cube ? unit_cube + mi : unit_shadow + mi, m.color);
    if (options.check_cancelled) options.check_cancelled();
  }
  gl.check("rendering the shadow maps");
}

}  // namespace loom::shading
