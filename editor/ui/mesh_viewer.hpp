// The mesh viewer: drawn with OpenGL in the editor's own context (no plugin),
// into an offscreen framebuffer shown as an ImGui image. Orbit with the left
// mouse button, zoom with the wheel; shaded or not, wireframe on or off, and
// UVs shown as a checker texture or as the UV layout itself (the mesh drawn
// at (u, v)). Shading is a headlight computed per vertex on the CPU, so the
// fixed-function pipeline of the 3.0 context suffices.
#pragma once

#include <vector>

#include <imgui.h>

#include "loom/mesh.hpp"

namespace loom::editor {

class MeshViewer {
 public:
  MeshViewer() = default;
  ~MeshViewer();
  MeshViewer(const MeshViewer&) = delete;
  MeshViewer& operator=(const MeshViewer&) = delete;

  void draw(const Mesh& mesh, const void* identity);
  // Where the rendering was shown last frame (screen pixels), for tests.
  ImVec2 shown_min() const { return shown_min_; }
  ImVec2 shown_max() const { return shown_max_; }

 private:
  void prepare(const Mesh& mesh);
  void render(const Mesh& mesh, int width, int height);
  struct VertexArrays {
    std::vector<float> positions, colors, uvs;
  };
  void make_framebuffer(int width, int height);
  void make_checker();
  VertexArrays vertex_arrays(const Mesh& mesh) const;
  void load_camera(float aspect) const;
  void draw_triangles(const Mesh& mesh, const VertexArrays& arrays) const;
  unsigned fbo_ = 0, color_ = 0, depth_ = 0, checker_ = 0;
  int fbo_width_ = 0, fbo_height_ = 0;
  const void* prepared_ = nullptr;
  std::vector<float> normals_;  // per vertex, area weighted
  float center_[3] = {0, 0, 0}, radius_ = 1;
  float yaw_ = 0.6f, pitch_ = 0.5f, distance_ = 3;
  ImVec2 shown_min_{0, 0}, shown_max_{0, 0};
  bool shaded_ = true, wireframe_ = false, checker_on_ = false, uv_layout_ = false;
};

}  // namespace loom::editor
