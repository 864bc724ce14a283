// A Scene's geometry and textures on the GPU for one render: vertex arrays
// (meshes with normals, UVs, tangents and colors; point sets; line sets) and
// the materials' maps. Created and destroyed with the context current.
#pragma once

#include <map>
#include <vector>

#include "gl_api.hpp"
#include "loom/scene.hpp"

namespace loom::shading {

struct GpuObject {
  enum class Kind { mesh, points, lines } kind = Kind::mesh;
  const SceneObject* source = nullptr;
  GLuint vao = 0;
  std::vector<GLuint> buffers;
  GLsizei count = 0;  // indices (mesh, lines) or points
  GLuint base_map = 0, normal_map = 0, displacement_map = 0;
};

// (M^-1)^T of the model matrix's linear part: how normals transform.
Eigen::Matrix3d normal_matrix(const Eigen::Matrix4d& model);
// Whether the object is drawn through the tessellation (displacement) programs.
bool displaced(const GpuObject& o, int tessellation);
// Draws a displaced mesh's patches. llvmpipe loses triangles (and time) when
// one draw tessellates more than about 10^5 triangles: such draws go in chunks.
void draw_patches(const GlApi& gl, GLsizei count, int level);

class GpuScene {
 public:
  GpuScene(const GlApi& gl, const Scene& scene);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  const std::vector<GpuObject>& objects() const { return objects_; }

 private:
  GLuint buffer(const void* data, std::size_t bytes);
  GLuint texture(const std::shared_ptr<const Image>& image, bool color);
  void attribute(GpuObject& o, GLuint location, GLuint buffer, int components);

  const GlApi& gl_;
  std::vector<GpuObject> objects_;
  std::vector<GLuint> buffers_;
  std::map<const Image*, GLuint> textures_;
};

}  // namespace loom::shading
