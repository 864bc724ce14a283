#include "embree_scene.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "displacement.hpp"
#include "loom/error.hpp"
#include "loom/hash.hpp"
#include "loom/numerics/tangent_frames.hpp"

namespace loom::pathtrace {

namespace {

// Fills a ray in three 16-byte stores. Embree's kernels load org|tnear and
// dir|time as 16-byte vectors first thing; filled field by field (4-byte
// stores), that load cannot be forwarded from the store buffer and waits for
// the stores to retire: perf put about 3.5 % of the path tracer's time on
// those two loads (docs/pathtrace.md, "Throughput, session 3").
void set_ray(RTCRay& r, const Vec3f& o, const Vec3f& d, float tfar, unsigned mask) {
#if defined(__SSE2__)
  _mm_store_ps(&r.org_x, _mm_setr_ps(o.x(), o.y(), o.z(), 0.f));  // tnear 0
  _mm_store_ps(&r.dir_x, _mm_setr_ps(d.x(), d.y(), d.z(), 0.f));  // time 0
  unsigned far_bits;
  std::memcpy(&far_bits, &tfar, sizeof far_bits);
  // tfar, mask, id 0, flags 0
  _mm_store_si128(reinterpret_cast<__m128i*>(&r.tfar), _mm_setr_epi32(int(far_bits), int(mask), 0, 0));
#else
  r = {o.x(), o.y(), o.z(), 0.f, d.x(), d.y(), d.z(), 0.f, tfar, mask, 0, 0};
#endif
}

template <class M>
void hash_matrix(Hasher& h, const M& m) {
  h.pod(std::int64_t(m.rows())).pod(std::int64_t(m.cols()));
  if (m.size() > 0) h.bytes(m.data(), sizeof(typename M::Scalar) * std::size_t(m.size()));
}

}  // namespace

bool displaced(const SceneObject& o, int level) {
  return level > 0 && o.mesh && o.mesh->has_uv() && o.material.displacement_map &&
         !o.material.displacement_map->empty() && o.material.displacement_scale != 0;
}

std::uint64_t geometry_key(const Scene& scene, int displacement_level) {
  Hasher h(0x70617468747261ull);
  h.pod(std::uint64_t(scene.objects.size()));
  for (const SceneObject& o : scene.objects) {
    hash_matrix(h, o.transform);
    h.pod(int(o.casts_shadow));
    h.pod(int(bool(o.material.normal_map)));
    if (displaced(o, displacement_level)) {
      const cv::Mat& map = o.material.displacement_map->pixels;
      h.pod(displacement_level).pod(o.material.displacement_scale);
      h.pod(map.rows).pod(map.cols).pod(map.type());
      for (int y = 0; y < map.rows; ++y) h.bytes(map.ptr(y), map.cols * map.elemSize());
    } else {
      h.pod(0);
    }
    if (o.mesh) {
      h.pod(1);
      hash_matrix(h, o.mesh->V);
      hash_matrix(h, o.mesh->F);
      hash_matrix(h, o.mesh->N);
      hash_matrix(h, o.mesh->UV);
      hash_matrix(h, o.mesh->C);
    } else if (o.points) {
      h.pod(2);
      hash_matrix(h, o.points->P);
      hash_matrix(h, o.points->radius);
      hash_matrix(h, o.points->C);
    } else {
      h.pod(3);
    }
  }
  return h.digest();
}

namespace {

struct ReleaseGeometry {
  void operator()(RTCGeometry g) const { rtcReleaseGeometry(g); }
};
using GeometryHandle = std::unique_ptr<RTCGeometryTy, ReleaseGeometry>;

// A new geometry buffer of `count` items of `size` bytes (Embree reports a
// failed allocation through the device and a null pointer).
void* new_buffer(RTCDevice device, RTCGeometry g, RTCBufferType type, RTCFormat format, std::size_t size,
                 std::size_t count) {
  void* b = rtcSetNewGeometryBuffer(g, type, 0, format, size, count);
  if (!b)
    throw Error("Embree could not allocate a geometry buffer of " + std::to_string(count) + " items (error " +
                std::to_string(int(rtcGetDeviceError(device))) + ")");
  return b;
}

// body(i) for i in [0, n), in parallel chunks; `cancelled` is asked before
// each chunk (a few milliseconds of work) and ends the loop with Cancelled.
template <class Body>
void for_each_index(std::size_t n, const std::function<bool()>& cancelled, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::size_t(1) << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      if (cancelled()) throw Cancelled();
                      for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
                    });
}

// A mesh in world space (displaced first when it is), with the attributes the
// integrator reads; extends `box` by its vertices.
TracedObject traced_mesh(const SceneObject& o, int displacement_level, Eigen::AlignedBox3f& box,
                         const std::function<bool()>& cancelled) {
  const Eigen::Matrix4d& T = o.transform;
  const Eigen::Matrix3d L = T.topLeftCorner<3, 3>();
  const Eigen::Matrix3d normal_matrix = L.inverse().transpose();
  std::optional<Mesh> displaced_copy;
  if (displaced(o, displacement_level))
    displaced_copy =
        displaced_mesh(*o.mesh, *o.material.displacement_map, o.material.displacement_scale, displacement_level);
  const Mesh& m = displaced_copy ? *displaced_copy : *o.mesh;
  const auto vertices = std::size_t(m.vertices()), faces = std::size_t(m.faces());
  TracedObject t;
  t.P.resize(vertices);
  for_each_index(vertices, cancelled, [&](std::size_t v) {
    t.P[v] = (L * m.V.row(Eigen::Index(v)).transpose() + T.block<3, 1>(0, 3)).cast<float>();
  });
  for (const Vec3f& p : t.P) box.extend(p);
  if (m.has_normals()) {
    t.N.resize(vertices);
    for_each_index(vertices, cancelled, [&](std::size_t v) {
      const Eigen::Vector3d n = normal_matrix * m.N.row(Eigen::Index(v)).transpose();
      t.N[v] = n.norm() > 0 ? Vec3f(n.normalized().cast<float>()) : Vec3f(Vec3f::Zero());
    });
  }
  if (m.has_uv()) {
    t.UV.resize(vertices);
    for_each_index(vertices, cancelled,
                   [&](std::size_t v) { t.UV[v] = m.UV.row(Eigen::Index(v)).transpose().cast<float>(); });
  }
  if (m.has_uv() && o.material.normal_map && !o.material.normal_map->empty()) {
    Eigen::MatrixX3d world(m.vertices(), 3), dPdu, dPdv;
    for (int v = 0; v < m.vertices(); ++v) world.row(v) = t.P[v].cast<double>().transpose();
    numerics::uv_tangents(world, m.F, m.UV, dPdu, dPdv);
    t.dPdu.resize(vertices);
    t.dPdv.resize(vertices);
    for (int v = 0; v < m.vertices(); ++v) {
      t.dPdu[v] = dPdu.row(v).transpose().cast<float>();
      t.dPdv[v] = dPdv.row(v).transpose().cast<float>();
    }
  }
  if (m.has_colors()) {
    t.C.resize(vertices);
    for_each_index(vertices, cancelled,
                   [&](std::size_t v) { t.C[v] = m.C.row(Eigen::Index(v)).transpose().cast<float>(); });
  }
  t.F.resize(faces);
  t.face_normal.resize(faces);
  for_each_index(faces, cancelled, [&](std::size_t f) {
    const Eigen::Vector3i tri = m.F.row(Eigen::Index(f)).transpose();
    t.F[f] = tri;
    const Vec3f n = (t.P[tri[1]] - t.P[tri[0]]).cross(t.P[tri[2]] - t.P[tri[0]]);
    const float n2 = n.squaredNorm();
    t.face_normal[f] = n2 > 0 && std::isfinite(n2) ? Vec3f(n / std::sqrt(n2)) : Vec3f(Vec3f::Zero());
  });
  return t;
}

GeometryHandle triangle_geometry(RTCDevice device, const TracedObject& t, const std::function<bool()>& cancelled) {
  GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
  if (!g) throw Error("Embree could not create a triangle geometry");
  auto* vb = static_cast<float*>(
      new_buffer(device, g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 3 * sizeof(float), t.P.size()));
  for_each_index(t.P.size(), cancelled, [&](std::size_t v) {
    for (int k = 0; k < 3; ++k) vb[3 * v + k] = t.P[v][k];
  });
  auto* ib = static_cast<unsigned*>(
      new_buffer(device, g.get(), RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), t.F.size()));
  for_each_index(t.F.size(), cancelled, [&](std::size_t f) {
    for (int k = 0; k < 3; ++k) ib[3 * f + k] = unsigned(t.F[f][k]);
  });
  return g;
}

// A point set as spheres in world space, a default radius of 1% of the
// cloud's extent when the set has none; extends `box` by the spheres.
TracedObject traced_points(const SceneObject& o, Eigen::AlignedBox3f& box) {
  const PointSet& ps = *o.points;
  const Eigen::Matrix3d L = o.transform.topLeftCorner<3, 3>();
  TracedObject t;
  t.spheres = true;
  Eigen::AlignedBox3d local;
  for (int p = 0; p < ps.points(); ++p) local.extend(Eigen::Vector3d(ps.P.row(p)));
  const double fallback = std::max(0.01 * local.diagonal().norm(), 1e-3);
  const double scale = std::cbrt(std::abs(L.determinant()));
  t.points.resize(ps.points());
  for (int p = 0; p < ps.points(); ++p) {
    const Eigen::Vector3d c = L * ps.P.row(p).transpose() + o.transform.block<3, 1>(0, 3);
    const double r = (ps.has_radius() ? ps.radius[p] : fallback) * scale;
    t.points[p] = Eigen::Vector4f(float(c.x()), float(c.y()), float(c.z()), float(r));
    box.extend(c.cast<float>() + Vec3f::Constant(float(r)));
    box.extend(c.cast<float>() - Vec3f::Constant(float(r)));
  }
  if (ps.has_colors()) {
    t.point_colors.resize(ps.points());
    for (int p = 0; p < ps.points(); ++p) t.point_colors[p] = ps.C.row(p).transpose().cast<float>();
  }
  return t;
}

GeometryHandle sphere_geometry(RTCDevice device, const TracedObject& t) {
  GeometryHandle g(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT));
  if (!g) throw Error("Embree could not create a sphere geometry");
  auto* pb = static_cast<float*>(
      new_buffer(device, g.get(), RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT4, 4 * sizeof(float), t.points.size()));
  for (std::size_t p = 0; p < t.points.size(); ++p)
    for (int k = 0; k < 4; ++k) pb[4 * p + k] = t.points[p][k];
  return g;
}

// Embree's build progress monitor (any build thread): false stops the build.
bool keep_building(void* cancelled, double /*done*/) {
  return !(*static_cast<const std::function<bool()>*>(cancelled))();
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene, int displacement_level, std::function<bool()> cancelled) {
  const auto start = std::chrono::steady_clock::now();
  if (!cancelled) cancelled = [] { return false; };
  const auto check_cancelled = [&cancelled] {
    if (cancelled()) throw Cancelled();
  };
  device_.reset(rtcNewDevice(nullptr));
  if (!device_)
    throw Error("Embree could not create a device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  scene_.reset(rtcNewScene(device_.get()));
  if (!scene_) throw Error("Embree could not create a scene (out of memory?)");
  rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneProgressMonitorFunction(scene_.get(), keep_building, &cancelled);
  Eigen::AlignedBox3f box;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    check_cancelled();
    TracedObject t;
    GeometryHandle g;
    if (o.mesh && o.mesh->faces() > 0) {
      t = traced_mesh(o, displacement_level, box, cancelled);
      g = triangle_geometry(device_.get(), t, cancelled);
      triangles_ += t.F.size();
    } else if (o.points && o.points->points() > 0) {
      t = traced_points(o, box);
      g = sphere_geometry(device_.get(), t);
    } else {
      if (o.lines) ++skipped_polylines_;
      continue;
    }
    t.scene_index = int(i);
    rtcSetGeometryMask(g.get(), o.casts_shadow ? (kCameraMask | kShadowMask) : kCameraMask);
    rtcCommitGeometry(g.get());
    const unsigned id = rtcAttachGeometry(scene_.get(), g.get());
    if (object_of_geometry_.size() <= id) object_of_geometry_.resize(id + 1, -1);
    object_of_geometry_[id] = int(objects_.size());
    objects_.push_back(std::move(t));
  }
  check_cancelled();
  rtcCommitScene(scene_.get());
  rtcSetSceneProgressMonitorFunction(scene_.get(), nullptr, nullptr);  // `cancelled` ends here
  check_cancelled();                                                   // the monitor stopped the build: no BVH
  if (rtcGetDeviceError(device_.get()) != RTC_ERROR_NONE)
    throw Error("Embree failed to build the BVH (out of memory?)");
  extent_ = box.isEmpty() ? 1.f : std::max(box.diagonal().norm(), 1e-6f);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool EmbreeScene::intersect(const Vec3f& o, const Vec3f& d, float tmax, SurfaceHit* hit,
                            bool coherent) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  RTCRayHit rh;
  set_ray(rh.ray, o, d, tmax, kCameraMask);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_.get(), &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  assemble_hit(o, d, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, hit);
  return true;
}

void EmbreeScene::surface_hit(const Vec3f& o, const Vec3f& d, float t, unsigned geometry, unsigned primitive, float u,
                              float v, SurfaceHit* hit) const {
  assemble_hit(o, d, t, geometry, primitive, u, v, hit);
}

// Inlined into intersect(), which runs for every closest-hit ray (a call
// there would pass eight arguments and the hit through memory).
[[gnu::always_inline]] inline void EmbreeScene::assemble_hit(const Vec3f& o, const Vec3f& d, float t, unsigned geometry,
                                                             unsigned primitive, float u, float v,
                                                             SurfaceHit* hit) const {
  const int index = object_of_geometry_[geometry];
  const TracedObject& obj = objects_[index];
  SurfaceHit& h = *hit;
  h.t = t;
  h.p = o + h.t * d;
  h.eps = offset_distance(h.p);
  h.object = index;
  h.prim = int(primitive);
  h.uv = Vec2f::Zero();
  h.color = Vec3f::Ones();
  if (obj.spheres) {
    const Eigen::Vector4f& s = obj.points[h.prim];
    const Vec3f n = h.p - s.head<3>();
    h.ng = n.squaredNorm() > 0 ? Vec3f(n.normalized()) : Vec3f(-d);
    h.ns = h.ng;
    if (!obj.point_colors.empty()) h.color = obj.point_colors[h.prim];
    return;
  }
  const Eigen::Vector3i& f = obj.F[h.prim];
  const float b1 = u, b2 = v, b0 = 1 - b1 - b2;
  h.ng = obj.face_normal[h.prim];
  // A degenerate triangle has no normal of its own: it faces the ray.
  if (h.ng.x() == 0 && h.ng.y() == 0 && h.ng.z() == 0) h.ng = -d;
  h.ns = h.ng;
  if (!obj.N.empty()) {
    const Vec3f ns = b0 * obj.N[f[0]] + b1 * obj.N[f[1]] + b2 * obj.N[f[2]];
    const float n2 = ns.squaredNorm();
    if (n2 > 1e-12f) {
      h.ns = ns / std::sqrt(n2);
      if (h.ns.dot(h.ng) < 0) h.ns = -h.ns;
    }
  }
  if (!obj.UV.empty()) h.uv = b0 * obj.UV[f[0]] + b1 * obj.UV[f[1]] + b2 * obj.UV[f[2]];
  if (!obj.dPdu.empty()) {
    h.dpdu = b0 * obj.dPdu[f[0]] + b1 * obj.dPdu[f[1]] + b2 * obj.dPdu[f[2]];
    h.dpdv = b0 * obj.dPdv[f[0]] + b1 * obj.dPdv[f[1]] + b2 * obj.dPdv[f[2]];
  }
  if (!obj.C.empty()) h.color = b0 * obj.C[f[0]] + b1 * obj.C[f[1]] + b2 * obj.C[f[2]];
}

bool EmbreeScene::occluded(const Vec3f& o, const Vec3f& d, float tmax) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  set_ray(ray, o, d, tmax, kShadowMask);
  rtcOccluded1(scene_.get(), &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

}  // namespace loom::pathtrace
