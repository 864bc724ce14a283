#include "mesh_denoising.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "loom/numerics/laplacian.hpp"
#include "loom/numerics/mesh_topology.hpp"

namespace loom::shading {

namespace {
std::vector<bool> boundary_vertices(const Eigen::MatrixX3i& F, int n) {
  std::vector<bool> b(n, false);
  for (const auto& loop : numerics::boundary_loops(F))
    for (int v : loop) b[v] = true;
  return b;
}

// One step of p_i += lambda (Σ w_ij p_j / Σ w_ij - p_i), W with zero diagonal.
Eigen::MatrixX3d averaged_step(const Eigen::MatrixX3d& V, const numerics::SparseMatrix& W,
                               const std::vector<bool>& fixed, double lambda) {
  Eigen::MatrixX3d out = V;
  for (int i = 0; i < W.outerSize(); ++i) {
    if (fixed[i]) continue;
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    double total = 0;
    for (numerics::SparseMatrix::InnerIterator it(W, i); it; ++it) {
      const double w = std::max(it.value(), 0.0);
      sum += w * V.row(it.index());
      total += w;
    }
    if (total > 0) out.row(i) += lambda * (sum / total - V.row(i));
  }
  return out;
}
}  // namespace

Eigen::VectorXd normal_displacements(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                     const Eigen::MatrixX3d& N) {
  const int n = static_cast<int>(V.rows());
  // uniform_weights is symmetric, so row i (as the column i of a
  // column-major matrix) lists vertex i's neighbours.
  const numerics::SparseMatrix W = numerics::uniform_weights(F, n);
  const std::vector<bool> fixed = boundary_vertices(F, n);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
    int count = 0;
    for (numerics::SparseMatrix::InnerIterator it(W, i); it; ++it, ++count) mean += V.row(it.index());
    if (count == 0) continue;
    d(i) = (V.row(i) - mean / count).dot(N.row(i));  // eq. 44-45
  }
  return d;
}

DisplacementMap bake_displacement(const Eigen::MatrixX2d& UV, const Eigen::VectorXd& d, int size, int K) {
  const int n = static_cast<int>(UV.rows());
  K = std::clamp(K, 1, std::max(n, 1));
  // Uniform grid over [0,1]² with about two vertices per cell.
  const int cells = std::clamp(static_cast<int>(std::sqrt(n / 2.0)), 1, 1024);
  std::vector<std::vector<int>> grid(cells * cells);
  auto cell_of = [&](double t) { return std::clamp(static_cast<int>(t * cells), 0, cells - 1); };
  for (int i = 0; i < n; ++i) grid[cell_of(UV(i, 1)) * cells + cell_of(UV(i, 0))].push_back(i);

  cv::Mat values(size, size, CV_64FC1);
  tbb::parallel_for(0, size, [&](int y) {
    std::vector<std::pair<double, int>> best;
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = 1 - (y + 0.5) / size;
      const int cx = cell_of(u), cy = cell_of(v);
      best.clear();
      // Grow square rings of cells until the K-th nearest is closer than the ring.
      for (int ring = 0; ring <= cells; ++ring) {
        for (int gy = cy - ring; gy <= cy + ring; ++gy)
          for (int gx = cx - ring; gx <= cx + ring; ++gx) {
            if (gx < 0 || gy < 0 || gx >= cells || gy >= cells) continue;
            if (std::max(std::abs(gx - cx), std::abs(gy - cy)) != ring) continue;
            for (int i : grid[gy * cells + gx]) {
              const double du = UV(i, 0) - u, dv = UV(i, 1) - v;
              best.emplace_back(du * du + dv * dv, i);
            }
          }
        if (static_cast<int>(best.size()) >= K) {
          std::nth_element(best.begin(), best.begin() + (K - 1), best.end());
          const double reach = static_cast<double>(ring) / cells;  // every unseen vertex is farther
          if (best[K - 1].first <= reach * reach) break;
        }
      }
      const int k = std::min<int>(K, static_cast<int>(best.size()));
      std::partial_sort(best.begin(), best.begin() + k, best.end());
      double sum = 0, total = 0;
      for (int j = 0; j < k; ++j) {
        if (best[j].first < 1e-24) {  // on a vertex
          sum = d(best[j].second);
          total = 1;
          break;
        }
        const double w = 1 / best[j].first;
        sum += w * d(best[j].second);
        total += w;
      }
      values.at<double>(y, x) = total > 0 ? sum / total : 0;
    }
  });
  double lo = 0, hi = 0;
  cv::minMaxLoc(values, &lo, &hi);
  DisplacementMap map;
  map.offset = lo;
  map.scale = hi > lo ? hi - lo : 1;
  values.convertTo(map.image, CV_32FC1, 1 / map.scale, -lo / map.scale);
  return map;
}

Eigen::VectorXd sample_displacement(const DisplacementMap& map, const Eigen::MatrixX2d& UV) {
  const int W = map.image.cols, H = map.image.rows;
  Eigen::VectorXd d(UV.rows());
  for (Eigen::Index i = 0; i < UV.rows(); ++i) {
    const double fx = std::clamp(UV(i, 0) * W - 0.5, 0.0, W - 1.0);
    const double fy = std::clamp((1 - UV(i, 1)) * H - 0.5, 0.0, H - 1.0);
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    const int x1 = std::min(x0 + 1, W - 1), y1 = std::min(y0 + 1, H - 1);
    const double ax = fx - x0, ay = fy - y0;
    auto at = [&](int x, int y) { return static_cast<double>(map.image.at<float>(y, x)); };
    const double t = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
    d(i) = map.offset + map.scale * t;
  }
  return d;
}

Eigen::MatrixX3d remove_displacement(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& N,
                                     const Eigen::VectorXd& d) {
  return V - (N.array().colwise() * d.array()).matrix();
}

Eigen::MatrixX3d smooth(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, SmoothingWeights weights,
                        int steps, double lambda) {
  const int n = static_cast<int>(V.rows());
  const std::vector<bool> fixed = boundary_vertices(F, n);
  Eigen::MatrixX3d P = V;
  const numerics::SparseMatrix uniform =
      weights == SmoothingWeights::uniform ? numerics::uniform_weights(F, n) : numerics::SparseMatrix();
  for (int s = 0; s < steps; ++s) {
    // cotangent_weights is symmetric: column i holds row i.
    P = averaged_step(P, weights == SmoothingWeights::uniform ? uniform : numerics::cotangent_weights(P, F), fixed,
                      lambda);
  }
  return P;
}

SurfaceError surface_error(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& clean, const Eigen::MatrixX3i& F) {
  SurfaceError e;
  if (V.rows() == 0) return e;
  e.rms_distance = std::sqrt((V - clean).rowwise().squaredNorm().mean());
  double sum = 0;
  int count = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    auto normal = [&](const Eigen::MatrixX3d& P) {
      const Eigen::Vector3d a = P.row(F(f, 0)), b = P.row(F(f, 1)), c = P.row(F(f, 2));
      return Eigen::Vector3d((b - a).cross(c - a));
    };
    const Eigen::Vector3d n1 = normal(V), n2 = normal(clean);
    if (n1.norm() == 0 || n2.norm() == 0) continue;
    sum += std::atan2(n1.cross(n2).norm(), n1.dot(n2));
    ++count;
  }
  e.mean_normal_angle = count ? sum / count : 0;
  return e;
}

}  // namespace loom::shading
