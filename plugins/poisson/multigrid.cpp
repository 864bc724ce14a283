#include "multigrid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <new>
#include <utility>

#include <Eigen/Core>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "exact_poisson.hpp"

namespace loom::poisson {

using V4 = Eigen::Array4f;

// Vectors that start at zero without being written: calloc's memory, which
// for pages fresh from the kernel (a cold process's) skips the fill. The
// solve's parallel loops then touch each page first, where one thread used to
// zero 100+ MB before them: a 1024² blend's node in one `loom run` took
// 0.42-0.56 s before, 0.22-0.31 s after (docs/limits.md, "Cold and warm").
// Reused memory is zeroed by calloc as before.
template <class T>
struct ZeroedAllocator {
  using value_type = T;
  ZeroedAllocator() = default;
  template <class U>
  ZeroedAllocator(const ZeroedAllocator<U>&) {}
  T* allocate(std::size_t n) {
    if (void* p = std::calloc(n, sizeof(T))) return static_cast<T*>(p);
    throw std::bad_alloc();
  }
  void deallocate(T* p, std::size_t) { std::free(p); }
  template <class U>
  void construct(U* p) {  // default-initialized, not value-initialized: calloc's zeros stay unwritten
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const ZeroedAllocator<U>&) const {
    return true;
  }
  template <class U>
  bool operator!=(const ZeroedAllocator<U>&) const {
    return false;
  }
};
using Field = std::vector<V4, ZeroedAllocator<V4>>;
using Level = MultigridPoisson::Level;

struct MultigridPoisson::Workspace {
  Field x, r, z, p, q;          // PCG on the finest level (q doubles as the V-cycle's residual)
  bool has_correction = false;  // x holds the correction of the last completed solve
  std::vector<Field> b, e;      // per coarse level: right-hand side and correction
  Field coarse_r;               // residual of a coarse level, consumed before recursing
};

namespace {

constexpr int kCoarsestUnknowns = 4096;  // solved directly below this size
constexpr float kInv[5] = {0.0f, 1.0f, 0.5f, 1.0f / 3.0f, 0.25f};  // 1/|N_p|, 0 off Ω
constexpr float kIn[5] = {0.0f, 1.0f, 1.0f, 1.0f, 1.0f};           // 1 on Ω

// Runs f(y) for every row, in parallel when the grid is worth it.
template <class F>
void for_rows(const Level& L, F&& f) {
  if (std::size_t(L.w) * L.h < 32768) {
    for (int y = 0; y < L.h; ++y) f(y);
    return;
  }
  const int grain = std::max(1, 16384 / L.w);
  tbb::parallel_for(tbb::blocked_range<int>(0, L.h, grain), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) f(y);
  });
}

// Combines row(y) over all rows with `join`, in a fixed order so results do
// not depend on the threads.
template <class T, class F, class Join>
T reduce_rows(const Level& L, F&& row, Join join) {
  const int grain = std::max(1, 16384 / L.w);
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, L.h, grain), T(T::Zero()),
      [&](const tbb::blocked_range<int>& r, T acc) {
        for (int y = r.begin(); y < r.end(); ++y) acc = join(acc, row(y));
        return acc;
      },
      join);
}

// One colour of red-black Gauss–Seidel on row y: x_p = (b_p + Σ_q x_q) / |N_p|
// on Ω. Colour kFromZero is the first red sweep from x = 0: red cells get
// b_p / |N_p|, black cells 0.
constexpr int kFromZero = 2;
void smooth_row(const Level& L, const Field& b, Field& x, int colour, int y) {
  const std::size_t s = L.stride;
  if (colour == kFromZero) {
    const std::size_t i0 = L.at(0, y);
    for (int c = 0; c < L.w; ++c) {
      const std::size_t i = i0 + c;
      x[i] = ((c + y) & 1) ? V4(V4::Zero()) : V4(b[i] * kInv[L.degree[i]]);
    }
    return;
  }
  for (int c = (y + colour) & 1; c < L.w; c += 2) {
    const std::size_t i = L.at(c, y);
    x[i] = (b[i] + x[i - 1] + x[i + 1] + x[i - s] + x[i + s]) * kInv[L.degree[i]];
  }
}

// The half-sweeps colours[0], colours[1], … (alternating colours) in one pass
// over memory, with the same result as running them one after the other:
// half-sweep j runs one row behind half-sweep j − 1, whose rows y ± 1 it reads.
// In parallel, each block of rows first does the part of that wavefront that
// needs no other block (a trapezoid: half-sweep j on rows [y0 + j, y1 − j)),
// then the triangles left at each block edge are filled in, in order.
// row_done(y) runs once row y is final (after the last half-sweep on it).
template <class RowDone>
void sweeps(const Level& L, const Field& b, Field& x, std::initializer_list<int> colours,
            RowDone&& row_done) {
  const int k = static_cast<int>(colours.size());
  const int* colour = colours.begin();
  const int block = std::max(4 * k, 32768 / L.w);
  const int blocks = (L.h + block - 1) / block;
  auto trapezoid = [&](int y0, int y1) {
    const int first = y0 == 0 ? 0 : 1, last = y1 == L.h ? 0 : 1;  // 1: shrink at an inner edge
    for (int y = y0; y < y1 + k; ++y)
      for (int j = 0; j < k; ++j) {
        const int row = y - j;
        if (row < y0 + first * j || row >= y1 - last * j) continue;
        smooth_row(L, b, x, colour[j], row);
        if (j == k - 1) row_done(row);
      }
  };
  auto triangle = [&](int edge) {  // half-sweep j on rows [edge − j, edge + j)
    for (int j = 1; j < k; ++j)
      for (int row = std::max(0, edge - j); row < std::min(L.h, edge + j); ++row) {
        smooth_row(L, b, x, colour[j], row);
        if (j == k - 1) row_done(row);
      }
  };
  if (blocks <= 1 || std::size_t(L.w) * L.h < 32768) {
    trapezoid(0, L.h);
    return;
  }
  tbb::parallel_for(0, blocks, [&](int i) { trapezoid(i * block, std::min(L.h, (i + 1) * block)); });
  tbb::parallel_for(1, blocks, [&](int i) { triangle(i * block); });
}

// r = b − A x on Ω, 0 elsewhere.
void residual(const Level& L, const Field& b, const Field& x, Field& r) {
  const std::size_t s = L.stride;
  for_rows(L, [&](int y) {
    for (std::size_t i = L.at(0, y), e = i + L.w; i < e; ++i) {
      const std::uint8_t d = L.degree[i];
      r[i] = (b[i] - float(d) * x[i] + x[i - 1] + x[i + 1] + x[i - s] + x[i + s]) * kIn[d];
    }
  });
}

// Bilinear weights of the cell-centred transfer: fine cells 2I−1, 2I, 2I+1,
// 2I+2 against coarse cell I.
constexpr float kW[4] = {0.25f, 0.75f, 0.75f, 0.25f};

// b_c = Pᵀ r_f on the coarse Ω.
void restrict_residual(const Level& F, const Field& r, const Level& C, Field& b) {
  const std::size_t s = F.stride;
  for_rows(C, [&](int J) {
    for (int I = 0; I < C.w; ++I) {
      const std::size_t o = C.at(I, J);
      if (C.degree[o] == 0) {
        b[o] = V4::Zero();
        continue;
      }
      V4 acc = V4::Zero();
      std::size_t row = F.at(2 * I - 1, 2 * J - 1);
      for (int a = 0; a < 4; ++a, row += s)
        acc += kW[a] * (kW[0] * r[row] + kW[1] * r[row + 1] + kW[2] * r[row + 2] +
                        kW[3] * r[row + 3]);
      b[o] = acc;
    }
  });
}

// x_f += P e_c on the fine Ω.
void prolong_add(const Level& C, const Field& e, const Level& F, Field& x) {
  const std::size_t s = C.stride;
  for_rows(F, [&](int y) {
    const int J = y >> 1;
    const std::ptrdiff_t oy = (y & 1) ? std::ptrdiff_t(s) : -std::ptrdiff_t(s);
    for (int xf = 0; xf < F.w; ++xf) {
      const std::size_t i = F.at(xf, y);
      if (F.degree[i] == 0) continue;
      const std::size_t c = C.at(xf >> 1, J);
      const std::ptrdiff_t ox = (xf & 1) ? 1 : -1;
      x[i] += 0.5625f * e[c] + 0.1875f * (e[c + ox] + e[c + oy]) + 0.0625f * e[c + ox + oy];
    }
  });
}

Level make_level(const cv::Mat1b& unknown) {
  Level L;
  L.w = unknown.cols;
  L.h = unknown.rows;
  L.stride = L.w + 4;
  L.degree.assign(L.size(), 0);
  for (int y = 0; y < L.h; ++y)
    for (int x = 0; x < L.w; ++x) {
      if (!unknown(y, x)) continue;
      L.degree[L.at(x, y)] = std::uint8_t((x > 0) + (x + 1 < L.w) + (y > 0) + (y + 1 < L.h));
      ++L.unknowns;
    }
  return L;
}

// A coarse cell is unknown when every child inside the grid is: Dirichlet
// cells win, so every coarse component keeps a boundary and stays definite.
cv::Mat1b coarsen(const cv::Mat1b& fine) {
  cv::Mat1b coarse((fine.rows + 1) / 2, (fine.cols + 1) / 2);
  for (int J = 0; J < coarse.rows; ++J)
    for (int I = 0; I < coarse.cols; ++I) {
      bool all = true;
      for (int y = 2 * J; y < std::min(2 * J + 2, fine.rows); ++y)
        for (int x = 2 * I; x < std::min(2 * I + 2, fine.cols); ++x) all = all && fine(y, x);
      coarse(J, I) = all ? 255 : 0;
    }
  return coarse;
}

Eigen::Array4d row_dot(const Level& L, const Field& u, const Field& v, int y) {
  Eigen::Array4d acc = Eigen::Array4d::Zero();
  for (std::size_t i = L.at(0, y), e = i + L.w; i < e; ++i) acc += (u[i] * v[i]).cast<double>();
  return acc;
}

struct Hierarchy {
  const std::vector<Level>& levels;
  const numerics::SparseCholesky& coarsest;
  const std::vector<std::size_t>& cells;
  MultigridPoisson::Workspace& ws;
  std::vector<Eigen::Array4d> rz_rows;  // b·x per row of the finest level, from the last V-cycle

  // r·z of PCG after vcycle(0, r, z, ·), summed in row order.
  Eigen::Array4d rz() const {
    Eigen::Array4d sum = Eigen::Array4d::Zero();
    for (const Eigen::Array4d& row : rz_rows) sum += row;
    return sum;
  }

  // x = V(b): one symmetric V-cycle from x = 0 on level l. r: scratch of level l.
  void vcycle(std::size_t l, const Field& b, Field& x, Field& r) {
    const Level& L = levels[l];
    if (l + 1 == levels.size()) {
      Eigen::MatrixXd B(cells.size(), 4);
      for (std::size_t k = 0; k < cells.size(); ++k) B.row(k) = b[cells[k]].cast<double>().transpose();
      const Eigen::MatrixXd X = coarsest.solve(B);
      std::fill(x.begin(), x.end(), V4::Zero());
      for (std::size_t k = 0; k < cells.size(); ++k) x[cells[k]] = X.row(k).transpose().cast<float>();
      if (l == 0)
        for (int y = 0; y < L.h; ++y) rz_rows[y] = row_dot(L, b, x, y);
      return;
    }
    sweeps(L, b, x, {kFromZero, 1, 0, 1}, [](int) {});
    residual(L, b, x, r);
    restrict_residual(L, r, levels[l + 1], ws.b[l + 1]);
    vcycle(l + 1, ws.b[l + 1], ws.e[l + 1], ws.coarse_r);
    prolong_add(levels[l + 1], ws.e[l + 1], L, x);
    // Reverse order: the V-cycle stays symmetric. On the finest level, b·x row
    // by row while the rows are in cache (PCG's r·z).
    sweeps(L, b, x, {1, 0, 1, 0}, [&](int y) {
      if (l == 0) rz_rows[y] = row_dot(L, b, x, y);
    });
  }
};

}  // namespace

MultigridPoisson::MultigridPoisson(const cv::Mat1b& unknown) {
  cv::Mat1b grid = unknown;
  levels_.push_back(make_level(grid));
  while (levels_.back().unknowns > kCoarsestUnknowns) {
    cv::Mat1b coarse = coarsen(grid);
    if (cv::countNonZero(coarse) == 0) break;
    grid = coarse;
    levels_.push_back(make_level(grid));
  }
  cv::Mat1i index;
  const numerics::SparseMatrix A = poisson_matrix(grid, index);
  const Level& last = levels_.back();
  coarsest_cells_.resize(A.rows());
  for (int y = 0; y < grid.rows; ++y)
    for (int x = 0; x < grid.cols; ++x)
      if (index(y, x) >= 0) coarsest_cells_[index(y, x)] = last.at(x, y);
  coarsest_.compute(A);
}

// The vectors of the last solve, reused unless another solve holds them.
std::shared_ptr<MultigridPoisson::Workspace> MultigridPoisson::take_workspace() const {
  {
    std::lock_guard<std::mutex> lock(workspace_mutex_);
    if (workspace_) return std::move(workspace_);
  }
  auto ws = std::make_shared<Workspace>();
  const std::size_t n = levels_[0].size();
  for (Field* v : {&ws->x, &ws->r, &ws->z, &ws->p, &ws->q}) v->resize(n);  // zeros (ZeroedAllocator)
  ws->b.resize(levels_.size());
  ws->e.resize(levels_.size());
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    ws->b[l].resize(levels_[l].size());
    ws->e[l].resize(levels_[l].size());
  }
  if (levels_.size() > 1) ws->coarse_r.resize(levels_[1].size());
  return ws;
}

// Over 80 lines on purpose: preconditioned CG read top to bottom, one pass over
// the rows per step, as the algorithm is written in Saad (2003), Alg. 9.1.
MultigridPoisson::Result MultigridPoisson::solve(const cv::Mat& b, cv::Mat& f, double tolerance,
                                                 int max_iterations, Start start,
                                                 const std::function<void()>& between) const {
  const std::shared_ptr<Workspace> ws = take_workspace();

  const Level& L = levels_[0];
  const int C = b.channels();
  const std::size_t s = L.stride;
  Field &x = ws->x, &r = ws->r, &z = ws->z, &p = ws->p, &q = ws->q;
  Hierarchy H{levels_, coarsest_, coarsest_cells_, *ws, std::vector<Eigen::Array4d>(L.h)};

  // PCG on the correction x = f − g, from x = 0 or the previous correction x₀:
  // r = b − A (g + x₀) (on Ω only; the boundary values are in b already).
  const bool warm = start == Start::previous_correction && ws->has_correction;
  ws->has_correction = false;
  for_rows(L, [&](int y) {
    const float* bv = b.ptr<float>(y);
    const float* fv = f.ptr<float>(y);
    for (int c = 0; c < L.w; ++c) {
      const std::size_t i = L.at(c, y);
      if (!warm) x[i] = V4::Zero();
      for (int k = C; k < 4; ++k) x[i][k] = 0.0f;  // lanes of channels the last solve had more of
      z[i] = x[i];
      q[i] = V4::Zero();
      if (L.degree[i] == 0) continue;
      for (int k = 0; k < C; ++k) {
        z[i][k] += fv[c * C + k];
        q[i][k] = bv[c * C + k];
      }
    }
  });
  residual(L, q, z, r);

  H.vcycle(0, r, z, q);
  p = z;
  Eigen::Array4d rz = H.rz();
  Result result;
  for (int it = 1; it <= max_iterations; ++it) {
    // q = A p and p·q in one pass.
    const Eigen::Array4d pq = reduce_rows<Eigen::Array4d>(
        L,
        [&](int y) {
          Eigen::Array4d acc = Eigen::Array4d::Zero();
          for (std::size_t i = L.at(0, y), e = i + L.w; i < e; ++i) {
            const std::uint8_t d = L.degree[i];
            q[i] = (float(d) * p[i] - p[i - 1] - p[i + 1] - p[i - s] - p[i + s]) * kIn[d];
            acc += (p[i] * q[i]).cast<double>();
          }
          return acc;
        },
        [](const Eigen::Array4d& a, const Eigen::Array4d& c) { return Eigen::Array4d(a + c); });
    const V4 alpha = (pq > 0).select(rz / pq.max(1e-300), 0.0).cast<float>();
    // x += α p, r −= α q, and the largest change.
    const V4 change = reduce_rows<V4>(
        L,
        [&](int y) {
          V4 m = V4::Zero();
          for (std::size_t i = L.at(0, y), e = i + L.w; i < e; ++i) {
            const V4 step = alpha * p[i];
            x[i] += step;
            r[i] -= alpha * q[i];
            m = m.max(step.abs());
          }
          return m;
        },
        [](const V4& a, const V4& c) { return V4(a.max(c)); });
    result.iterations = it;
    result.last_change = change.maxCoeff();
    if (between) between();
    if (result.last_change <= tolerance) break;
    H.vcycle(0, r, z, q);
    const Eigen::Array4d rz_next = H.rz();
    const V4 beta = (rz > 0).select(rz_next / rz.max(1e-300), 0.0).cast<float>();
    rz = rz_next;
    for_rows(L, [&](int y) {
      for (std::size_t i = L.at(0, y), e = i + L.w; i < e; ++i) p[i] = z[i] + beta * p[i];
    });
  }
  for_rows(L, [&](int y) {  // f = g + x
    float* fv = f.ptr<float>(y);
    for (int c = 0; c < L.w; ++c) {
      const std::size_t i = L.at(c, y);
      if (L.degree[i] == 0) continue;
      for (int k = 0; k < C; ++k) fv[c * C + k] += x[i][k];
    }
  });
  ws->has_correction = true;
  std::lock_guard<std::mutex> lock(workspace_mutex_);
  workspace_ = ws;
  return result;
}

}  // namespace loom::poisson
