#include "gpu_scene.hpp"

#include <algorithm>
#include <cstdint>

#include <opencv2/core.hpp>

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
}  // namespace

GLuint GpuScene::buffer(const void* data, std::size_t bytes) {
  GLuint b = 0;
  gl_.CreateBuffers(1, &b);
  gl_.NamedBufferData(b, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
  buffers_.push_back(b);
  return b;
}

void GpuScene::attribute(GpuObject& o, GLuint location, GLuint b, int components) {
  gl_.VertexArrayVertexBuffer(o.vao, location, b, 0, static_cast<GLsizei>(components * sizeof(float)));
  gl_.VertexArrayAttribFormat(o.vao, location, components, GL_FLOAT, GL_FALSE, 0);
  gl_.VertexArrayAttribBinding(o.vao, location, location);
  gl_.EnableVertexArrayAttrib(o.vao, location);
}

// Images are stored top row first; GL's t = 0 is the first row uploaded, so
// the shaders look up (u, 1 - v). Gray maps are read as gray in every channel.
GLuint GpuScene::texture(const std::shared_ptr<const Image>& image, bool color) {
  if (!image || image->empty()) return 0;
  auto it = textures_.find(image.get());
  if (it != textures_.end()) return it->second;
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
  textures_.emplace(image.get(), t);
  return t;
}

GpuScene::GpuScene(const GlApi& gl, const Scene& scene) : gl_(gl) {
  for (const SceneObject& object : scene.objects) {
    GpuObject o;
    o.source = &object;
    gl_.CreateVertexArrays(1, &o.vao);
    if (object.mesh) {
      const Mesh& m = *object.mesh;
      o.kind = GpuObject::Kind::mesh;
      const Eigen::MatrixX3d N = m.has_normals() ? Eigen::MatrixX3d(m.N) : numerics::vertex_normals(m.V, m.F);
      const Eigen::MatrixX2d UV = m.has_uv() ? Eigen::MatrixX2d(m.UV) : Eigen::MatrixX2d::Zero(m.V.rows(), 2);
      Eigen::MatrixX3d dPdu, dPdv;
      if (m.has_uv()) {
        numerics::uv_tangents(m.V, m.F, m.UV, dPdu, dPdv);
      } else {
        dPdu = dPdv = Eigen::MatrixX3d::Zero(m.V.rows(), 3);
      }
      const Eigen::MatrixX3d C = m.has_colors() ? Eigen::MatrixX3d(m.C) : Eigen::MatrixX3d::Ones(m.V.rows(), 3);
      const auto upload = [&](GLuint location, const Eigen::MatrixXd& values) {
        const auto f = floats(values);
        attribute(o, location, buffer(f.data(), f.size() * sizeof(float)), static_cast<int>(values.cols()));
      };
      upload(0, m.V);
      upload(1, N);
      upload(2, UV);
      upload(3, dPdu);
      upload(4, dPdv);
      upload(5, C);
      const auto idx = indices(m.F);
      gl_.VertexArrayElementBuffer(o.vao, buffer(idx.data(), idx.size() * sizeof(unsigned)));
      o.count = static_cast<GLsizei>(idx.size());
      o.base_map = texture(object.material.base_color_map, true);
      o.normal_map = texture(object.material.normal_map, false);
      o.displacement_map = texture(object.material.displacement_map, false);
    } else if (object.points) {
      const PointSet& p = *object.points;
      o.kind = GpuObject::Kind::points;
      const auto fp = floats(p.P);
      attribute(o, 0, buffer(fp.data(), fp.size() * sizeof(float)), 3);
      const Eigen::VectorXd r = p.has_radius() ? Eigen::VectorXd(p.radius) : Eigen::VectorXd::Ones(p.P.rows());
      const auto fr = floats(r);
      attribute(o, 1, buffer(fr.data(), fr.size() * sizeof(float)), 1);
      const Eigen::MatrixX3d C = p.has_colors() ? Eigen::MatrixX3d(p.C) : Eigen::MatrixX3d::Ones(p.P.rows(), 3);
      const auto fc = floats(C);
      attribute(o, 2, buffer(fc.data(), fc.size() * sizeof(float)), 3);
      o.count = static_cast<GLsizei>(p.P.rows());
    } else if (object.lines) {
      const Polylines& l = *object.lines;
      o.kind = GpuObject::Kind::lines;
      const auto fp = floats(l.P);
      attribute(o, 0, buffer(fp.data(), fp.size() * sizeof(float)), 3);
      const Eigen::MatrixX3d C = l.has_colors() ? Eigen::MatrixX3d(l.C) : Eigen::MatrixX3d::Ones(l.P.rows(), 3);
      const auto fc = floats(C);
      attribute(o, 5, buffer(fc.data(), fc.size() * sizeof(float)), 3);
      const auto idx = indices(l.E);
      gl_.VertexArrayElementBuffer(o.vao, buffer(idx.data(), idx.size() * sizeof(unsigned)));
      o.count = static_cast<GLsizei>(idx.size());
    }
    objects_.push_back(o);
  }
}

GpuScene::~GpuScene() {
  for (const GpuObject& o : objects_) gl_.DeleteVertexArrays(1, &o.vao);
  if (!buffers_.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
  for (const auto& [image, t] : textures_) gl_.DeleteTextures(1, &t);
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

}  // namespace loom::shading
