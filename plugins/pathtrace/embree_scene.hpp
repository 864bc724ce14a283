// A loom::Scene's geometry in world space with one Embree 3 BVH over it.
// Built once per geometry (key: geometry_key) and kept in the PathTrace
// node's scratch: materials, lights, camera and sample counts do not enter
// the key, so re-renders that change only those reuse the BVH.
// Meshes become triangle geometries, PointSets sphere points; Polylines are
// not traced (the rasterizer draws them).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <embree3/rtcore.h>

#include "loom/scene.hpp"
#include "sampling.hpp"

namespace loom::pathtrace {

// Everything the BVH depends on: each object's geometry and transform,
// whether it is normal mapped (UV tangents are kept), its displacement map
// and scale, and the subdivision level of displacement.
std::uint64_t geometry_key(const Scene& scene, int displacement_level = 0);

// Whether an object is displaced before the BVH build at this level: a mesh
// with UVs, a displacement map and a nonzero scale.
bool displaced(const SceneObject& object, int displacement_level);

struct TracedObject {
  int scene_index = -1;  // into Scene::objects
  bool spheres = false;
  // Triangles (world space).
  std::vector<Vec3f> P, N, C;
  std::vector<Vec2f> UV;
  // World-space dP/du, dP/dv per vertex (loom::numerics::uv_tangents), kept
  // only for normal-mapped meshes with UVs.
  std::vector<Vec3f> dPdu, dPdv;
  std::vector<Eigen::Vector3i> F;
  // Per triangle, precomputed for the hit: unit geometric normal by the
  // winding (zero for a degenerate triangle).
  std::vector<Vec3f> face_normal;
  // Sphere points (world space): x, y, z, radius; per-point color or empty.
  std::vector<Eigen::Vector4f> points;
  std::vector<Vec3f> point_colors;
};

// A point on a surface, as the integrator needs it.
struct SurfaceHit {
  Vec3f p;
  Vec3f ng;  // unit geometric normal: outward by the triangle's winding, outward for spheres
  Vec3f ns;  // unit shading normal (interpolated vertex normals), on ng's side
  Vec2f uv{0, 0};
  Vec3f dpdu{0, 0, 0}, dpdv{0, 0, 0};  // interpolated, when the object keeps tangents
  Vec3f color{1, 1, 1};  // per-vertex / per-point color, multiplies base color
  float t = 0;
  float eps = 0;  // offset_distance(p), computed once per hit
  int object = -1;  // into EmbreeScene::objects
  int prim = -1;
};

class EmbreeScene {
 public:
  // `skipped` counts objects that are not traced (polylines, empty geometry).
  // Displaced meshes (displaced()) are subdivided `displacement_level` times
  // and displaced (displacement.hpp) before the build. `cancelled` is asked
  // between objects and their stages, and by Embree's progress monitor during
  // the BVH build, which stops when it says yes: the constructor then throws
  // loom::Cancelled.
  explicit EmbreeScene(const Scene& scene, int displacement_level = 0, std::function<bool()> cancelled = {});
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  const std::vector<TracedObject>& objects() const { return objects_; }
  int skipped_polylines() const { return skipped_polylines_; }
  double build_seconds() const { return build_seconds_; }
  std::size_t triangles() const { return triangles_; }
  float extent() const { return extent_; }  // bounding-box diagonal

  // `direction` is unit. `coherent`: a camera ray (neighbouring rays alike).
  bool intersect(const Vec3f& origin, const Vec3f& direction, float tmax, SurfaceHit* hit,
                 bool coherent = false) const;
  // The hit that Embree found along origin + t * direction, on its geometry
  // and primitive at barycentrics (u, v): what intersect() returns, for a
  // caller that traced the ray itself (in a packet).
  void surface_hit(const Vec3f& origin, const Vec3f& direction, float t, unsigned geometry, unsigned primitive, float u,
                   float v, SurfaceHit* hit) const;
  // Any shadow-casting surface between origin and origin + tmax * direction.
  bool occluded(const Vec3f& origin, const Vec3f& direction, float tmax) const;
  // A ray origin moved off the surface to the side `direction` leaves by.
  // (Inline, like shadow_segment: a Vec3f returned from another translation unit
  // comes back through memory as three 4-byte stores that the caller's 8-byte
  // load cannot forward.)
  Vec3f offset(const SurfaceHit& hit, const Vec3f& direction) const {
    const float eps = hit.eps > 0 ? hit.eps : offset_distance(hit.p);
    return hit.p + (hit.ng.dot(direction) >= 0 ? eps : -eps) * hit.ng;
  }
  // How far offset() moves a point at p: float precision at p's magnitude.
  float offset_distance(const Vec3f& p) const {
    return 1e-4f * (1 + p.cwiseAbs().maxCoeff()) + 1e-6f * extent_;
  }
  // The shadow ray from hit (offset) to a point on a light; both ends are
  // kept off their surfaces. tmax <= 0: nothing between them to test.
  struct Segment {
    Vec3f origin, direction;  // direction unit
    float tmax;
  };
  Segment shadow_segment(const SurfaceHit& hit, const Vec3f& light_point) const {
    const Vec3f origin = offset(hit, light_point - hit.p);
    const Vec3f d = light_point - origin;
    const float length2 = d.squaredNorm(), inv_length = inv_sqrt(length2);
    // The segment stops short of the light's surface by the same margin.
    return {origin, d * inv_length, length2 * inv_length - offset_distance(light_point)};
  }

  // Embree's own handle and ray masks, for measuring Embree alone on the
  // same BVH (bench_pathtrace rays): camera and bounce rays carry
  // kCameraMask, shadow rays kShadowMask (objects with casts_shadow off lack it).
  RTCScene rtc_scene() const { return scene_.get(); }
  static constexpr unsigned kCameraMask = 1, kShadowMask = 2;

 private:
  // Released by their owners, also when the constructor throws half way.
  struct ReleaseDevice {
    void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
  };
  struct ReleaseScene {
    void operator()(RTCScene s) const { rtcReleaseScene(s); }
  };
  // What surface_hit() returns, inlined into intersect().
  void assemble_hit(const Vec3f& origin, const Vec3f& direction, float t, unsigned geometry, unsigned primitive,
                    float u, float v, SurfaceHit* hit) const;
  std::unique_ptr<RTCDeviceTy, ReleaseDevice> device_;  // declared first: released last
  std::unique_ptr<RTCSceneTy, ReleaseScene> scene_;
  std::vector<TracedObject> objects_;
  std::vector<int> object_of_geometry_;
  int skipped_polylines_ = 0;
  double build_seconds_ = 0;
  std::size_t triangles_ = 0;
  float extent_ = 1;
};

}  // namespace loom::pathtrace
