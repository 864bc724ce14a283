#include "emitters.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "loom/error.hpp"

namespace loom::mpm {
namespace {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

// Items between two cancellation checks in the loops over particles.
constexpr std::size_t kChunk = std::size_t(1) << 16;

// Cells of size h along each axis of [lo, hi] (at least one; rounded up or
// down) and their product, refused above `limit` before anything is cast or
// allocated: counted in double, since a huge shape over a fine spacing
// overflows long.
template <int D>
std::pair<Eigen::Matrix<long, D, 1>, long> cell_counts(const Vec<D>& lo, const Vec<D>& hi, double h, bool round_up,
                                                       double limit, const char* too_many) {
  Eigen::Matrix<double, D, 1> count;
  for (int d = 0; d < D; ++d) {
    const double c = (hi[d] - lo[d]) / h;
    count[d] = std::max(1.0, round_up ? std::ceil(c) : std::floor(c));
  }
  if (!(count.prod() <= limit)) throw Error(too_many);
  return {count.template cast<long>(), static_cast<long>(count.prod())};
}

// Points of the lattice spacing·(i + 1/2) inside [lo, hi], optionally jittered
// uniformly within their cell.
template <int D>
std::vector<Vec<D>> lattice(const Vec<D>& lo, const Vec<D>& hi, double h, bool jitter, std::mt19937_64& rng,
                            const std::function<void()>& check_cancelled) {
  const auto counts = cell_counts<D>(lo, hi, h, false, 100'000'000,
                                     "the shape holds more than 100 million particles at this spacing");
  const Eigen::Matrix<long, D, 1>& n = counts.first;
  const long total = counts.second;
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<Vec<D>> points;
  points.reserve(static_cast<std::size_t>(total));
  for (long k = 0; k < total; ++k) {
    if (std::size_t(k) % kChunk == 0) check_cancelled();
    Vec<D> x;
    long r = k;
    for (int d = D - 1; d >= 0; --d) {
      const long i = r % n[d];
      r /= n[d];
      x[d] = lo[d] + h * (static_cast<double>(i) + 0.5 + (jitter ? u(rng) : 0.0));
    }
    points.push_back(x);
  }
  return points;
}

// Bridson's Poisson-disk sampling with minimum distance h, 30 candidates a point.
template <int D>
std::vector<Vec<D>> poisson_disk(const Vec<D>& lo, const Vec<D>& hi, double h, std::mt19937_64& rng,
                                 const std::function<void(double, double)>& progress) {
  const double cell = h / std::sqrt(static_cast<double>(D));
  const auto counts = cell_counts<D>(lo, hi, cell, true, 200'000'000,
                                     "the shape is too large for Poisson-disk sampling at this spacing");
  const Eigen::Matrix<long, D, 1>& n = counts.first;
  const long total = counts.second;
  std::vector<int> grid(static_cast<std::size_t>(total), -1);
  auto cell_of = [&](const Vec<D>& x, Eigen::Matrix<long, D, 1>& c) {
    for (int d = 0; d < D; ++d)
      c[d] = std::clamp(static_cast<long>((x[d] - lo[d]) / cell), 0L, n[d] - 1);
  };
  auto flat = [&](const Eigen::Matrix<long, D, 1>& c) {
    long k = 0;
    for (int d = 0; d < D; ++d) k = k * n[d] + c[d];
    return k;
  };
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> gauss;
  std::vector<Vec<D>> points, active;
  auto accept = [&](const Vec<D>& x) {
    for (int d = 0; d < D; ++d)
      if (x[d] < lo[d] || x[d] > hi[d]) return false;
    Eigen::Matrix<long, D, 1> c;
    cell_of(x, c);
    // neighbours within 2 cells (cell = h/√D, so ⌈√D⌉ ≤ 2 suffices)
    const int span = 5;
    long combos = 1;
    for (int d = 0; d < D; ++d) combos *= span;
    for (long k = 0; k < combos; ++k) {
      Eigen::Matrix<long, D, 1> q;
      bool ok = true;
      for (int d = D - 1, r = static_cast<int>(k); d >= 0; --d, r /= span) {
        q[d] = c[d] + r % span - 2;
        if (q[d] < 0 || q[d] >= n[d]) ok = false;
      }
      if (!ok) continue;
      const int j = grid[static_cast<std::size_t>(flat(q))];
      if (j >= 0 && (points[static_cast<std::size_t>(j)] - x).squaredNorm() < h * h) return false;
    }
    grid[static_cast<std::size_t>(flat(c))] = static_cast<int>(points.size());
    points.push_back(x);
    active.push_back(x);
    return true;
  };
  Vec<D> first;
  for (int d = 0; d < D; ++d) first[d] = lo[d] + u01(rng) * (hi[d] - lo[d]);
  accept(first);
  // The sampling ends with about 31% (2D) or 11% (3D) of the h/√D cells
  // filled (measured on boxes): the estimate of the count for progress.
  const double expected = static_cast<double>(total) * (D == 2 ? 0.31 : 0.11);
  std::size_t next_report = 0;
  while (!active.empty()) {
    if (progress && points.size() >= next_report) {
      progress(static_cast<double>(points.size()), std::max(expected, static_cast<double>(points.size()) + 1));
      next_report = points.size() + 4096;
    }
    std::uniform_int_distribution<std::size_t> pick(0, active.size() - 1);
    const std::size_t a = pick(rng);
    const Vec<D> centre = active[a];
    bool found = false;
    for (int t = 0; t < 30 && !found; ++t) {
      Vec<D> dir;
      for (int d = 0; d < D; ++d) dir[d] = gauss(rng);
      if (dir.norm() == 0) continue;
      const double r = h * (1 + u01(rng));  // uniform radius in [h, 2h]
      found = accept(centre + dir.normalized() * r);
    }
    if (!found) {
      active[a] = active.back();
      active.pop_back();
    }
  }
  return points;
}

// The candidates inside the shape, in order; the test (a winding number for
// meshes) runs in parallel.
template <int D>
std::vector<Vec<D>> candidates_inside(const std::vector<Vec<D>>& candidates,
                                      const std::function<bool(const Vec<D>&)>& inside,
                                      const std::function<void()>& check_cancelled) {
  std::vector<char> in(candidates.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        if (i % 16 == 0) check_cancelled();  // a mesh's winding number: 16 cost ms
                        in[i] = inside(candidates[i]);
                      }
                    });
  std::vector<Vec<D>> out;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (in[i]) out.push_back(candidates[i]);
  return out;
}

// The permutation that sorts `keys` stably: an LSD radix sort, 16 bits a
// pass, skipping the digits that every key shares (a Morton key over a
// shape's cells varies in its low 20-30 bits: two passes).
std::vector<std::uint32_t> stable_order(const std::vector<std::uint64_t>& keys,
                                        const std::function<void()>& check_cancelled) {
  const std::size_t n = keys.size();
  std::vector<std::uint32_t> order(n), next(n);
  std::iota(order.begin(), order.end(), 0u);
  std::uint64_t any = 0, all = ~std::uint64_t(0);
  for (const std::uint64_t k : keys) any |= k, all &= k;
  for (int shift = 0; shift < 64; shift += 16) {
    if ((((any ^ all) >> shift) & 0xffff) == 0) continue;
    std::vector<std::size_t> start(65537, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (i % kChunk == 0) check_cancelled();
      ++start[((keys[i] >> shift) & 0xffff) + 1];
    }
    for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
    for (std::size_t i = 0; i < n; ++i) {
      if (i % kChunk == 0) check_cancelled();
      next[start[(keys[order[i]] >> shift) & 0xffff]++] = order[i];
    }
    order.swap(next);
  }
  return order;
}

// The points in Morton order of cells of 4·spacing: neighbours in space are
// neighbours in memory, and the solver's blocks read their particles from few
// places. Equal keys keep their order.
// The Morton key of x's cell of size `cell` (20 bits per axis, interleaved).
template <int D>
std::uint64_t morton_key(const Vec<D>& x, const Vec<D>& lo, double cell) {
  std::uint32_t c[D];
  for (int d = 0; d < D; ++d) c[d] = static_cast<std::uint32_t>(std::clamp((x[d] - lo[d]) / cell, 0.0, 1048575.0));
  std::uint64_t key = 0;
  for (int bit = 19; bit >= 0; --bit)
    for (int d = 0; d < D; ++d) key = (key << 1) | ((c[d] >> bit) & 1u);
  return key;
}

template <int D>
std::vector<Vec<D>> in_morton_order(const std::vector<Vec<D>>& points, const Vec<D>& lo, double spacing,
                                    const std::function<void()>& check_cancelled) {
  std::vector<std::uint64_t> keys(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kChunk),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      check_cancelled();
                      for (std::size_t i = r.begin(); i < r.end(); ++i) keys[i] = morton_key<D>(points[i], lo, 4 * spacing);
                    });
  const std::vector<std::uint32_t> order = stable_order(keys, check_cancelled);
  std::vector<Vec<D>> sorted(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) sorted[i] = points[order[i]];
  return sorted;
}

}  // namespace

template <int D>
Particles<D> fill_shape(const std::function<bool(const Vec<D>&)>& inside, const Vec<D>& lo,
                        const Vec<D>& hi, const EmitOptions& o) {
  if (!(o.density > 0)) throw Error("density must be positive");
  if (!(o.E > 0)) throw Error("E (Young's modulus) must be positive");
  if (o.material != Material::fluid && !(o.nu > -1 && o.nu < 0.5))
    throw Error("nu (Poisson's ratio) must be in (-1, 0.5)");
  if (!(o.spacing > 0)) throw Error("spacing must be positive");
  for (int d = 0; d < D; ++d)
    if (!(hi[d] > lo[d])) throw Error("the shape is empty (its bounds have no extent)");
  std::mt19937_64 rng(o.seed);
  std::vector<Vec<D>> candidates;
  switch (o.sampling) {
    case Sampling::grid:
      candidates = lattice<D>(lo, hi, o.spacing, false, rng, o.check_cancelled);
      break;
    case Sampling::jittered:
      candidates = lattice<D>(lo, hi, o.spacing, true, rng, o.check_cancelled);
      break;
    case Sampling::poisson: candidates = poisson_disk<D>(lo, hi, o.spacing, rng, o.progress); break;
    case Sampling::random: {
      if (o.count <= 0) throw Error("count must be positive for random sampling");
      std::uniform_real_distribution<double> u(0, 1);
      for (long tries = 0; static_cast<int>(candidates.size()) < o.count; ++tries) {
        if (tries > 100L * o.count + 1000000)
          throw Error("the shape is too thin to place random particles in its bounds");
        if (std::size_t(tries) % kChunk == 0) o.check_cancelled();
        Vec<D> x;
        for (int d = 0; d < D; ++d) x[d] = lo[d] + u(rng) * (hi[d] - lo[d]);
        if (inside(x)) candidates.push_back(x);
      }
      break;
    }
  }
  const std::vector<Vec<D>> points =
      in_morton_order<D>(candidates_inside(candidates, inside, o.check_cancelled), lo, o.spacing, o.check_cancelled);
  if (points.empty())
    throw Error("the shape holds no particle at this spacing: lower spacing or enlarge it");
  double volume = o.particle_volume;
  if (!(volume > 0)) {
    // The shape's volume, counted on the regular lattice at `spacing`.
    std::mt19937_64 unused(0);
    const long in = static_cast<long>(
        candidates_inside(lattice<D>(lo, hi, o.spacing, false, unused, o.check_cancelled), inside, o.check_cancelled)
            .size());
    volume = std::pow(o.spacing, D) * static_cast<double>(std::max(in, 1L)) /
             static_cast<double>(points.size());
  }
  Particles<D> ps;
  ps.reserve(points.size());
  const Lame lame = lame_parameters(o.material, o.E, o.nu);
  const Vec<D> v = o.velocity.head<D>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i % kChunk == 0) o.check_cancelled();
    ps.add(points[i], v, o.material, lame, o.density * volume, volume, o.color);
  }
  return ps;
}

template Particles<2> fill_shape<2>(const std::function<bool(const Vec<2>&)>&, const Vec<2>&,
                                    const Vec<2>&, const EmitOptions&);
template Particles<3> fill_shape<3>(const std::function<bool(const Vec<3>&)>&, const Vec<3>&,
                                    const Vec<3>&, const EmitOptions&);

double winding_number(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                      const Eigen::Vector3d& q) {
  // Van Oosterom–Strackee solid angle of each triangle, summed, over 4π.
  double total = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose() - q;
    const Eigen::Vector3d b = V.row(F(f, 1)).transpose() - q;
    const Eigen::Vector3d c = V.row(F(f, 2)).transpose() - q;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double det = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(det, den);
  }
  return total / (4 * M_PI);
}

}  // namespace loom::mpm
