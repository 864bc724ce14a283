// A Scene's geometry and textures on the GPU: vertex arrays (meshes with
// normals, UVs, tangents and colors; point sets; line sets) and the
// materials' maps. They stay in a GpuCache between renders, keyed by the
// address of the immutable value they were made from (held, so the address
// stays valid): a static mesh is uploaded once, not every frame. Created and
// destroyed with the context current.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "gl_api.hpp"
#include "loom/scene.hpp"

namespace loom::shading {

struct GpuObject {
  enum class Kind { mesh, points, lines } kind = Kind::mesh;
  const SceneObject* source = nullptr;
  GLuint vao = 0;
  GLsizei count = 0;  // indices (mesh, lines) or points
  GLuint base_map = 0, normal_map = 0, displacement_map = 0;
  int closed = 0;              // meshes: closed_orientation (+1 outward, -1 inward, 0 open)
  Eigen::AlignedBox3d bounds;  // meshes: object-space bounds
};

class GpuCache {
 public:
  explicit GpuCache(const GlApi& gl) : gl_(gl) {}
  ~GpuCache();
  GpuCache(const GpuCache&) = delete;
  GpuCache& operator=(const GpuCache&) = delete;

  struct Geometry {
    GLuint vao = 0;
    std::vector<GLuint> buffers;
    GLsizei count = 0;
    int closed = 0;
    Eigen::AlignedBox3d bounds;
  };
  // The geometry made from `owner`, made by `make` the first time.
  template <class Make>
  const Geometry& geometry(const std::shared_ptr<const void>& owner, Make make) {
    auto it = geometry_.find(owner.get());
    if (it == geometry_.end()) it = geometry_.emplace(owner.get(), GeometryEntry{owner, make(), false}).first;
    it->second.used = true;
    return it->second.geometry;
  }
  // The texture of an image (0 for none), uploaded the first time.
  GLuint texture(const std::shared_ptr<const Image>& image, bool color);
  // Releases what no render used since the last call.
  void release_unused();

 private:
  struct GeometryEntry {
    std::shared_ptr<const void> owner;
    Geometry geometry;
    bool used = false;
  };
  struct TextureEntry {
    std::shared_ptr<const Image> owner;
    GLuint texture = 0;
    bool used = false;
  };
  void release(Geometry& g);
  const GlApi& gl_;
  std::map<const void*, GeometryEntry> geometry_;
  std::map<std::pair<const Image*, bool>, TextureEntry> textures_;
};

// (M^-1)^T of the model matrix's linear part: how normals transform.
Eigen::Matrix3d normal_matrix(const Eigen::Matrix4d& model);
// Whether the object is drawn through the tessellation (displacement) programs.
bool displaced(const GpuObject& o, int tessellation);
// Draws a displaced mesh's patches. llvmpipe loses triangles (and time) when
// one draw tessellates more than about 10^5 triangles: such draws go in chunks.
void draw_patches(const GlApi& gl, GLsizei count, int level);
// Draws a mesh's triangles (`count` indices). Above 2^18 triangles, in
// batches, each finished before `check_cancelled` (may throw; may be empty)
// is asked: a cancel waits for one batch at most. Same image: same order.
void draw_triangles(const GlApi& gl, GLsizei count, const std::function<void()>& check_cancelled);

class GpuScene {
 public:
  // `check_cancelled` (may be empty) is asked before each object's upload.
  GpuScene(const GlApi& gl, const Scene& scene, GpuCache& cache, const std::function<void()>& check_cancelled);

  const std::vector<GpuObject>& objects() const { return objects_; }

 private:
  std::vector<GpuObject> objects_;
};

}  // namespace loom::shading
