#include "mesh_viewer.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace loom::editor {

MeshViewer::~MeshViewer() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (color_) glDeleteTextures(1, &color_);
  if (checker_) glDeleteTextures(1, &checker_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
}

void MeshViewer::prepare(const Mesh& mesh) {
  const int n = mesh.vertices();
  normals_.assign(std::size_t(n) * 3, 0.0f);
  for (int f = 0; f < mesh.faces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const Eigen::Vector3d face = (b - a).cross(c - a);  // length: twice the area
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) normals_[std::size_t(mesh.F(f, k)) * 3 + d] += float(face[d]);
  }
  for (int v = 0; v < n; ++v) {
    float* p = &normals_[std::size_t(v) * 3];
    const float length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (length > 0)
      for (int d = 0; d < 3; ++d) p[d] /= length;
  }
  if (n > 0) {
    const Eigen::RowVector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
    for (int d = 0; d < 3; ++d) center_[d] = float((lo[d] + hi[d]) / 2);
    radius_ = std::max(1e-6f, float((hi - lo).norm() / 2));
  }
}

// The offscreen target the mesh is drawn into, (re)made at the viewer's size.
void MeshViewer::make_framebuffer(int width, int height) {
  if (fbo_ && width == fbo_width_ && height == fbo_height_) return;
  if (!fbo_) {
    glGenFramebuffers(1, &fbo_);
    glGenTextures(1, &color_);
    glGenRenderbuffers(1, &depth_);
  }
  glBindTexture(GL_TEXTURE_2D, color_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  fbo_width_ = width;
  fbo_height_ = height;
}

// The 8-pixel checker that shows a parameterization's stretch, made once.
void MeshViewer::make_checker() {
  if (checker_) return;
  std::vector<std::uint8_t> pixels(64 * 64 * 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::uint8_t v = ((x / 8 + y / 8) % 2) ? 235 : 60;
      for (int k = 0; k < 3; ++k) pixels[std::size_t(y * 64 + x) * 3 + k] = v;
    }
  glGenTextures(1, &checker_);
  glBindTexture(GL_TEXTURE_2D, checker_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, 64, 64, 0, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
}

// Per vertex: the position drawn (centred, or the UV layout), the colour
// shaded by the normal against the eye, and the checker's coordinates.
MeshViewer::VertexArrays MeshViewer::vertex_arrays(const Mesh& mesh) const {
  const int n = mesh.vertices();
  VertexArrays a;
  a.positions.resize(std::size_t(n) * 3);
  a.colors.resize(std::size_t(n) * 3);
  a.uvs.resize(std::size_t(n) * 2);
  const float cy = std::cos(yaw_), sy = std::sin(yaw_), cp = std::cos(pitch_), sp = std::sin(pitch_);
  const float eye[3] = {cp * sy, sp, cp * cy};  // direction to the eye
  for (int v = 0; v < n; ++v) {
    float* p = &a.positions[std::size_t(v) * 3];
    if (uv_layout_ && mesh.has_uv()) {
      p[0] = float(mesh.UV(v, 0)) * 2 - 1;
      p[1] = float(mesh.UV(v, 1)) * 2 - 1;
      p[2] = 0;
    } else {
      for (int d = 0; d < 3; ++d) p[d] = float(mesh.V(v, d)) - center_[d];
    }
    float shade = 1;
    if (shaded_ && !uv_layout_) {
      const float* nn = &normals_[std::size_t(v) * 3];
      shade = 0.25f + 0.75f * std::abs(nn[0] * eye[0] + nn[1] * eye[1] + nn[2] * eye[2]);
    }
    for (int d = 0; d < 3; ++d)
      a.colors[std::size_t(v) * 3 + d] = shade * (mesh.has_colors() ? float(mesh.C(v, d)) : (d == 2 ? 0.85f : 0.8f));
    if (mesh.has_uv()) {
      a.uvs[std::size_t(v) * 2] = float(mesh.UV(v, 0)) * 8;
      a.uvs[std::size_t(v) * 2 + 1] = float(mesh.UV(v, 1)) * 8;
    }
  }
  return a;
}

// Camera: orbit around the bounding box centre; the UV layout is seen from above.
void MeshViewer::load_camera(float aspect) const {
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glMatrixMode(GL_PROJECTION);
  if (uv_layout_) {
    glOrtho(-1.1 * aspect, 1.1 * aspect, -1.1, 1.1, -1, 1);
    return;
  }
  const double near = 0.01 * radius_, far = 100.0 * radius_, h = near * 0.5;
  glFrustum(-h * aspect, h * aspect, -h, h, near, far);
  glMatrixMode(GL_MODELVIEW);
  glTranslatef(0, 0, -distance_ * radius_);
  glRotatef(pitch_ * 57.29578f, 1, 0, 0);
  glRotatef(-yaw_ * 57.29578f, 0, 1, 0);
}

// The triangles (checkered where asked), then their edges where asked.
void MeshViewer::draw_triangles(const Mesh& mesh, const VertexArrays& a) const {
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, a.positions.data());
  glColorPointer(3, GL_FLOAT, 0, a.colors.data());
  const bool textured = checker_on_ && mesh.has_uv();
  if (textured) {
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, checker_);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, 0, a.uvs.data());
  }
  std::vector<unsigned> indices(std::size_t(mesh.faces()) * 3);
  for (int f = 0; f < mesh.faces(); ++f)
    for (int k = 0; k < 3; ++k) indices[std::size_t(f) * 3 + k] = unsigned(mesh.F(f, k));
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1, 1);
  glDrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, indices.data());
  glDisable(GL_POLYGON_OFFSET_FILL);
  if (textured) {
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisable(GL_TEXTURE_2D);
  }
  if (wireframe_ || uv_layout_) {
    glDisableClientState(GL_COLOR_ARRAY);
    glColor3f(0.05f, 0.05f, 0.08f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, indices.data());
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glDisableClientState(GL_VERTEX_ARRAY);
  glDisableClientState(GL_COLOR_ARRAY);
}

// Draws the mesh into the offscreen target, leaving ImGui's GL state as found.
void MeshViewer::render(const Mesh& mesh, int width, int height) {
  make_framebuffer(width, height);
  make_checker();
  GLint viewport[4];
  glGetIntegerv(GL_VIEWPORT, viewport);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width, height);
  glClearColor(0.16f, 0.16f, 0.18f, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(0);
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  const VertexArrays arrays = vertex_arrays(mesh);
  load_camera(float(width) / float(height));
  draw_triangles(mesh, arrays);
  glDisable(GL_DEPTH_TEST);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
}

void MeshViewer::draw(const Mesh& mesh, const void* identity) {
  if (identity != prepared_) {
    prepare(mesh);
    prepared_ = identity;
  }
  ImGui::Checkbox("shaded", &shaded_);
  ImGui::SameLine();
  ImGui::Checkbox("wireframe", &wireframe_);
  if (mesh.has_uv()) {
    ImGui::SameLine();
    ImGui::Checkbox("UV checker", &checker_on_);
    ImGui::SameLine();
    ImGui::Checkbox("UV layout", &uv_layout_);
  }
  ImGui::SameLine();
  ImGui::TextDisabled("%d vertices, %d faces", mesh.vertices(), mesh.faces());
  ImVec2 size = ImGui::GetContentRegionAvail();
  const int width = std::max(16, int(size.x)), height = std::max(16, int(size.y) - 4);
  if (mesh.vertices() > 0 && mesh.faces() > 0) render(mesh, width, height);
  ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(color_)), ImVec2(float(width), float(height)),
               ImVec2(0, 1), ImVec2(1, 0));  // the framebuffer's rows run bottom up
  shown_min_ = ImGui::GetItemRectMin();
  shown_max_ = ImGui::GetItemRectMax();
  if (ImGui::IsItemHovered()) {
    ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
      yaw_ += io.MouseDelta.x * 0.01f;
      pitch_ = std::clamp(pitch_ + io.MouseDelta.y * 0.01f, -1.55f, 1.55f);
    }
    if (io.MouseWheel != 0) distance_ = std::clamp(distance_ * std::pow(0.9f, io.MouseWheel), 1.2f, 50.0f);
  }
}

}  // namespace loom::editor
