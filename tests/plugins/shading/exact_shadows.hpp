// The exact shadow mask of a rendered image, by casting a ray from each
// pixel's world position to the light with Embree (test and bench only; the
// plugin never uses Embree), and the misclassification rate of a shadow
// image against it.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "loom/scene.hpp"

namespace loom::shading::exact {

struct ShadowComparison {
  long compared = 0, wrong = 0, excluded_edges = 0;
  long shadowed = 0;  // compared pixels in the exact shadow
  double rate() const { return compared ? double(wrong) / compared : 0; }
  // Misclassified pixels per pixel of exact shadow: the scene-independent view.
  double rate_of_shadow() const { return shadowed ? double(wrong) / shadowed : 0; }
};

// true_lit: CV_8U, 1 where the light is visible from the pixel's surface
// point, 0 where occluded, 255 where not comparable (background, surfaces
// facing away from the light, geometric edges).
inline cv::Mat exact_visibility(const Scene& scene, const Light& light, const cv::Mat& position,
                                const cv::Mat& normal) {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene rs = rtcNewScene(device);
  for (const SceneObject& o : scene.objects) {
    if (!o.mesh || !o.casts_shadow) continue;
    const Mesh& m = *o.mesh;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.V.rows()));
    for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
      const Eigen::Vector4d p = o.transform * Eigen::Vector4d(m.V(i, 0), m.V(i, 1), m.V(i, 2), 1);
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(p[k]);
    }
    auto* f = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), m.F.rows()));
    for (Eigen::Index i = 0; i < m.F.rows(); ++i)
      for (int k = 0; k < 3; ++k) f[3 * i + k] = static_cast<unsigned>(m.F(i, k));
    rtcCommitGeometry(g);
    rtcAttachGeometry(rs, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(rs);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  cv::Mat lit(position.rows, position.cols, CV_8U, cv::Scalar(255));
  for (int y = 0; y < position.rows; ++y)
    for (int x = 0; x < position.cols; ++x) {
      const cv::Vec3f n = normal.at<cv::Vec3f>(y, x);
      if (n.dot(n) < 0.5) continue;  // background
      const cv::Vec4f p = position.at<cv::Vec4f>(y, x);
      const Eigen::Vector3d P(p[0], p[1], p[2]), N(n[0], n[1], n[2]);
      Eigen::Vector3d L;
      double distance = 1e30;
      if (light.kind == Light::Kind::directional) {
        L = -light.direction.normalized();
      } else {
        L = light.position - P;
        distance = L.norm();
        L /= distance;
      }
      if (N.dot(L) <= 0.02) continue;  // facing away: dark by shading, not by shadow
      RTCRay ray;
      const Eigen::Vector3d o = P + N * 1e-4;
      ray.org_x = float(o.x()), ray.org_y = float(o.y()), ray.org_z = float(o.z());
      ray.dir_x = float(L.x()), ray.dir_y = float(L.y()), ray.dir_z = float(L.z());
      ray.tnear = 1e-4f;
      ray.tfar = float(distance);
      ray.mask = 0xFFFFFFFF;
      ray.flags = 0;
      ray.time = 0;
      rtcOccluded1(rs, &context, &ray);
      lit.at<unsigned char>(y, x) = ray.tfar < 0 ? 0 : 1;  // rtcOccluded1 sets tfar = -inf on a hit
    }
  rtcReleaseScene(rs);
  rtcReleaseDevice(device);
  // Geometric edges: a normal that differs from a neighbor's is not comparable.
  cv::Mat out = lit.clone();
  for (int y = 1; y + 1 < lit.rows; ++y)
    for (int x = 1; x + 1 < lit.cols; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (cv::norm(normal.at<cv::Vec3f>(y, x) - normal.at<cv::Vec3f>(y + dy, x + dx)) > 0.05)
            out.at<unsigned char>(y, x) = 255;
  return out;
}

// Pixels where the shadow image (visibility >= 0.5 is lit) disagrees with
// the exact mask, excluding a one-pixel band at the exact shadow's edges.
inline ShadowComparison compare_shadows(const cv::Mat& exact_lit, const cv::Mat& shadow) {
  ShadowComparison c;
  for (int y = 1; y + 1 < exact_lit.rows; ++y)
    for (int x = 1; x + 1 < exact_lit.cols; ++x) {
      const unsigned char e = exact_lit.at<unsigned char>(y, x);
      if (e == 255) continue;
      bool edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const unsigned char q = exact_lit.at<unsigned char>(y + dy, x + dx);
          edge |= q != 255 && q != e;
        }
      if (edge) {
        ++c.excluded_edges;
        continue;
      }
      ++c.compared;
      c.shadowed += e == 0;
      c.wrong += (shadow.at<float>(y, x) >= 0.5f) != (e == 1);
    }
  return c;
}

}  // namespace loom::shading::exact
