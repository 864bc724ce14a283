#include "gpu_scene.hpp"

#include <algorithm>
#include <cstdint>

#include <opencv2/core.hpp>

#include "closed_surface.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace loom::shading {

namespace {
std::vector<float> floats(const Eigen::MatrixXd& m) {
  const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> f = m.cast<float>();
  return std::vector<float>(f.data(), f.data() + f.size());
}
std::vector<unsigned> indices(const Eigen::MatrixXi& m) {
  const Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  return std::vector<unsigned>(r.data(), r.data() + r.size());
}

GLuint buffer(const GlApi& gl, GpuCache::Geometry& g, const void* data, std::size_t bytes) {
  GLuint b = 0;
  gl.CreateBuffers(1, &b);
  gl.NamedBufferData(b, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
  g.buffers.push_back(b);
  return b;
}

void attribute(const GlApi& gl, GpuCache::Geometry& g, GLuint location, int components,
               const std::vector<float>& values) {
  const GLuint b = buffer(gl, g, values.data(), values.size() * sizeof(float));
  gl.VertexArrayVertexBuffer(g.vao, location, b, 0, static_cast<GLsizei>(components * sizeof(float)));
  gl.VertexArrayAttribFormat(g.vao, location, components, GL_FLOAT, GL_FALSE, 0);
  gl.VertexArrayAttribBinding(g.vao, location, location);
  gl.EnableVertexArrayAttrib(g.vao, location);
}

void attribute(const GlApi& gl, GpuCache::Geometry& g, GLuint location, const Eigen::MatrixXd& values) {
  attribute(gl, g, location, static_cast<int>(values.cols()), floats(values));
}

void elements(const GlApi& gl, GpuCache::Geometry& g, const Eigen::MatrixXi& m) {
  const auto idx = indices(m);
  gl.VertexArrayElementBuffer(g.vao, buffer(gl, g, idx.data(), idx.size() * sizeof(unsigned)));
  g.count = static_cast<GLsizei>(idx.size());
}

// The vertex arrays are made first, asking `check_cancelled` between them
// (they are the slow part of a big mesh's upload), so that a cancel leaves
// no GL object behind; then they are uploaded.
GpuCache::Geometry mesh_geometry(const GlApi& gl, const Mesh& m, const std::function<void()>& check_cancelled) {
  struct Attribute {
    GLuint location;
    int components;
    std::vector<float> values;
  };
  std::vector<Attribute> attributes;
  const auto add = [&](GLuint location, const Eigen::MatrixXd& values) {
    attributes.push_back({location, static_cast<int>(values.cols()), floats(values)});
    if (check_cancelled) check_cancelled();
  };
  add(0, m.V);
  add(1, m.has_normals() ? Eigen::MatrixXd(m.N) : Eigen::MatrixXd(numerics::vertex_normals(m.V, m.F)));
  add(2, m.has_uv() ? Eigen::MatrixXd(m.UV) : Eigen::MatrixXd::Zero(m.V.rows(), 2));
  Eigen::MatrixX3d dPdu, dPdv;
  if (m.has_uv()) {
    numerics::uv_tangents(m.V, m.F, m.UV, dPdu, dPdv);
  } else {
    dPdu = dPdv = Eigen::MatrixX3d::Zero(m.V.rows(), 3);
  }
  add(3, dPdu);
  add(4, dPdv);
  add(5, m.has_colors() ? Eigen::MatrixXd(m.C) : Eigen::MatrixXd::Ones(m.V.rows(), 3));
  GpuCache::Geometry g;
  gl.CreateVertexArrays(1, &g.vao);
  for (const Attribute& a : attributes) attribute(gl, g, a.location, a.components, a.values);
  elements(gl, g, m.F);
  g.closed = closed_orientation(m.V, m.F);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) g.bounds.extend(Eigen::Vector3d(m.V.row(i).transpose()));
  return g;
}

GpuCache::Geometry point_geometry(const GlApi& gl, const PointSet& p) {
  GpuCache::Geometry g;
  gl.CreateVertexArrays(1, &g.vao);
  attribute(gl, g, 0, p.P);
  attribute(gl, g, 1, p.has_radius() ? Eigen::VectorXd(p.radius) : Eigen::VectorXd::Ones(p.P.rows()));
  attribute(gl, g, 2, p.has_colors() ? Eigen::MatrixX3d(p.C) : Eigen::MatrixX3d::Ones(p.P.rows(), 3));
  g.count = static_cast<GLsizei>(p.P.rows());
  return g;
}

GpuCache::Geometry line_geometry(const GlApi& gl, const Polylines& l) {
  GpuCache::Geometry g;
  gl.CreateVertexArrays(1, &g.vao);
  attribute(gl, g, 0, l.P);
  attribute(gl, g, 5, l.has_colors() ? Eigen::MatrixX3d(l.C) : Eigen::MatrixX3d::Ones(l.P.rows(), 3));
  elements(gl, g, l.E);
  return g;
}

}  // namespace

// Images are stored top row first; GL's t = 0 is the first row uploaded, so
// the shaders look up (u, 1 - v). Gray maps are read as gray in every channel.
GLuint GpuCache::texture(const std::shared_ptr<const Image>& image, bool color) {
  if (!image || image->empty()) return 0;
  auto it = textures_.find({image.get(), color});
  if (it != textures_.end()) {
    it->second.used = true;
    return it->second.texture;
  }
  const Image linear = color && image->encoding == Encoding::srgb ? with_encoding(*image, Encoding::linear) : *image;
  cv::Mat px = linear.pixels.isContinuous() ? linear.pixels : linear.pixels.clone();
  const int ch = px.channels();
  static const GLenum internal[] = {GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
  static const GLenum format[] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
  GLuint t = 0;
  gl_.CreateTextures(GL_TEXTURE_2D, 1, &t);
  int levels = 1;
  for (int s = std::max(px.cols, px.rows); s > 1; s /= 2) ++levels;
  gl_.TextureStorage2D(t, levels, internal[ch - 1], px.cols, px.rows);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.TextureSubImage2D(t, 0, 0, 0, px.cols, px.rows, format[ch - 1], GL_FLOAT, px.data);
  gl_.GenerateTextureMipmap(t);
  gl_.TextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  gl_.TextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TextureParameteri(t, GL_TEXTURE_WRAP_S, GL_REPEAT);
  gl_.TextureParameteri(t, GL_TEXTURE_WRAP_T, GL_REPEAT);
  if (ch <= 2) {
    const GLint swizzle[] = {GL_RED, GL_RED, GL_RED, ch == 2 ? GL_GREEN : GL_ONE};
    gl_.TextureParameteriv(t, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  }
  textures_.emplace(std::make_pair(image.get(), color), TextureEntry{image, t, true});
  return t;
}

void GpuCache::release(Geometry& g) {
  gl_.DeleteVertexArrays(1, &g.vao);
  if (!g.buffers.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(g.buffers.size()), g.buffers.data());
}

void GpuCache::release_unused() {
  for (auto it = geometry_.begin(); it != geometry_.end();) {
    if (it->second.used) {
      it->second.used = false;
      ++it;
    } else {
      release(it->second.geometry);
      it = geometry_.erase(it);
    }
  }
  for (auto it = textures_.begin(); it != textures_.end();) {
    if (it->second.used) {
      it->second.used = false;
      ++it;
    } else {
      gl_.DeleteTextures(1, &it->second.texture);
      it = textures_.erase(it);
    }
  }
}

GpuCache::~GpuCache() {
  for (auto& [key, e] : geometry_) release(e.geometry);
  for (auto& [key, e] : textures_) gl_.DeleteTextures(1, &e.texture);
}

GpuScene::GpuScene(const GlApi& gl, const Scene& scene, GpuCache& cache, const std::function<void()>& check_cancelled) {
  for (const SceneObject& object : scene.objects) {
    if (check_cancelled) check_cancelled();
    GpuObject o;
    o.source = &object;
    const GpuCache::Geometry* g = nullptr;
    if (object.mesh) {
      o.kind = GpuObject::Kind::mesh;
      g = &cache.geometry(object.mesh, [&] { return mesh_geometry(gl, *object.mesh, check_cancelled); });
      o.base_map = cache.texture(object.material.base_color_map, true);
      o.normal_map = cache.texture(object.material.normal_map, false);
      o.displacement_map = cache.texture(object.material.displacement_map, false);
    } else if (object.points) {
      o.kind = GpuObject::Kind::points;
      g = &cache.geometry(object.points, [&] { return point_geometry(gl, *object.points); });
    } else if (object.lines) {
      o.kind = GpuObject::Kind::lines;
      g = &cache.geometry(object.lines, [&] { return line_geometry(gl, *object.lines); });
    }
    if (g) {
      o.vao = g->vao;
      o.count = g->count;
      o.closed = g->closed;
      o.bounds = g->bounds;
    }
    objects_.push_back(o);
  }
}

Eigen::Matrix3d normal_matrix(const Eigen::Matrix4d& model) {
  return model.topLeftCorner<3, 3>().inverse().transpose();
}

bool displaced(const GpuObject& o, int tessellation) {
  return o.displacement_map && o.source->material.displacement_scale != 0 && tessellation > 0;
}

void draw_patches(const GlApi& gl, GLsizei count, int level) {
  const GLsizei per_draw = 3 * std::max(1, 16384 / std::max(1, level * level));
  for (GLsizei first = 0; first < count; first += per_draw)
    gl.DrawElements(GL_PATCHES, std::min(per_draw, count - first), GL_UNSIGNED_INT,
                    reinterpret_cast<const void*>(static_cast<std::uintptr_t>(first) * sizeof(unsigned)));
}

void draw_triangles(const GlApi& gl, GLsizei count, const std::function<void()>& check_cancelled) {
  constexpr GLsizei per_draw = 3 << 18;
  if (count <= per_draw || !check_cancelled) {
    gl.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    return;
  }
  for (GLsizei first = 0; first < count; first += per_draw) {
    gl.DrawElements(GL_TRIANGLES, std::min(per_draw, count - first), GL_UNSIGNED_INT,
                    reinterpret_cast<const void*>(static_cast<std::uintptr_t>(first) * sizeof(unsigned)));
    gl.Finish();
    check_cancelled();
  }
}

}  // namespace loom::shading
