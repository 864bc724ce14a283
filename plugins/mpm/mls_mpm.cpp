#include "mls_mpm.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include <emmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/partitioner.h>

#include "constitutive.hpp"
#include "loom/error.hpp"

namespace loom::mpm {
namespace {

// Quadratic B-spline weights of the three nodes base, base+1, base+2 along each
// axis, fx = x/Δx − base ∈ [0.5, 1.5) (Hu et al. 2018, as in mpm88).
template <int D>
struct Weights {
  Eigen::Matrix<int, D, 1> base;
  Eigen::Matrix<double, D, 1> fx;
  double w[D][3];
  Weights(const Eigen::Matrix<double, D, 1>& x, double inv_dx) {
    for (int d = 0; d < D; ++d) {
      const double xg = x[d] * inv_dx;
      base[d] = static_cast<int>(xg - 0.5);
      fx[d] = xg - base[d];
      w[d][0] = 0.5 * (1.5 - fx[d]) * (1.5 - fx[d]);
      w[d][1] = 0.75 - (fx[d] - 1) * (fx[d] - 1);
      w[d][2] = 0.5 * (fx[d] - 0.5) * (fx[d] - 0.5);
    }
  }
};

// Two doubles of a node (8-byte aligned), read and written as doubles. Through
// std::memcpy the scatter's stores could alias any object, so the compiler loaded
// every array's address and every constant again after each particle's nodes, 28
// instructions a particle (measured in docs/mpm.md).
using UnalignedPair = double __attribute__((vector_size(16), aligned(8)));
Pair load(const double* p) { return *reinterpret_cast<const UnalignedPair*>(p); }
void store(double* p, Pair v) { *reinterpret_cast<UnalignedPair*>(p) = v; }
Pair splat(double a) { return Pair{a, a}; }

// x + o a for a stencil offset o ∈ {0, 1, 2}, given a2 = a + a (= 2a exactly). The
// scalar code added a·0 = ±0 for o = 0: that changes only the sign of a zero, and
// the sums these terms go into start at +0, which adding ±0 leaves at +0 (an
// infinite a gave NaN there and ±∞ here: either way the step is reported diverged).
Pair offset(Pair x, int o, Pair a, Pair a2) { return o == 0 ? x : o == 1 ? x + a : x + a2; }

// P2G of one particle into its 3^D nodes (node = momentum, mass; `row` its lowest
// node): node += w_i (q + A o) and w_i m, o ∈ {0,1,2}^D (see Solver::p2g).
template <int D>
void scatter(double* grid, long row, const long* stride, const Weights<D>& w,
             const Eigen::Matrix<double, D, 1>& q, const Eigen::Matrix<double, D, D>& A, double m) {
  Pair a[D][2], a2[D][2];
  for (int c = 0; c < D; ++c) {
    a[c][0] = Pair{A(0, c), A(1, c)};
    a[c][1] = Pair{D == 3 ? A(D - 1, c) : 0.0, 0.0};  // 3D: row 2 and the mass lane's 0
    a2[c][0] = a[c][0] + a[c][0];
    a2[c][1] = a[c][1] + a[c][1];
  }
  // 3D: the second pair is (q_z, m), so that node (p_z, m) += w (q_z + ..., m + 0) in one.
  const Pair q0{q[0], q[1]}, q1{D == 3 ? q[D - 1] : 0.0, m};
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) {
    const Pair qi0 = offset(q0, i, a[0][0], a2[0][0]), qi1 = offset(q1, i, a[0][1], a2[0][1]);
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const double wij = w.w[0][i] * w.w[1][j];
      const Pair qij0 = offset(qi0, j, a[1][0], a2[1][0]), qij1 = offset(qi1, j, a[1][1], a2[1][1]);
      double* node = grid + (D + 1) * (row + i * stride[0] + j * stride[1]);
      if constexpr (D == 2) {
        store(node, load(node) + splat(wij) * qij0);
        node[2] += wij * m;
      } else {
#pragma GCC unroll 3
        for (int k = 0; k < 3; ++k, node += 4) {
          const Pair wijk = splat(wij * w.w[2][k]);
          store(node, load(node) + wijk * offset(qij0, k, a[2][0], a2[2][0]));
          store(node + 2, load(node + 2) + wijk * offset(qij1, k, a[2][1], a2[2][1]));
        }
      }
    }
  }
}

// Three terms at the offsets o = 0, 1, 2 along one axis: their sum, and their sum
// weighted by the offset, t₁ + 2 t₂.
Pair sum3(const Pair (&t)[3]) { return (t[0] + t[1]) + t[2]; }
Pair moment3(const Pair (&t)[3]) { return t[1] + (t[2] + t[2]); }

// G2P's sums over the particle's 3^D nodes, v = Σ w v_o and Bo = Σ w v_o oᵀ, one
// axis at a time. The weight is a product over the axes, w = w_i w_j w_k, and the
// offset is o = (i, j, k), so Σ_i w_i Σ_j w_j Σ_k w_k (1, i, j, k) v_ijk gives v and
// Bo's columns: a row's three nodes give its sum and its moment in k, three rows a
// plane's sums and moments, three planes the totals. Each node is weighted and
// added once, and no sum runs through all 3^D nodes, so the core overlaps them.
template <int D>
void gather(const double* grid, long row, const long* stride, const Weights<D>& w,
            Eigen::Matrix<double, D, 1>& v_out, Eigen::Matrix<double, D, D>& Bo_out) {
  // 3D: pairs (x, y) and (z, mass); the mass lane's sums are not used.
  constexpr int P = D == 3 ? 2 : 1;
  Pair weight[D][3];
  for (int d = 0; d < D; ++d)
    for (int o = 0; o < 3; ++o) weight[d][o] = splat(w.w[d][o]);
  Pair v[P], Bo[D][P];
  if constexpr (D == 2) {
    Pair sum[3], moment_y[3];  // per i, over its 3 nodes, weighted by w_i
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const double* node = grid + 3 * (row + i * stride[0]);
      Pair t[3];
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) t[j] = weight[1][j] * load(node + 3 * j * stride[1]);
      sum[i] = weight[0][i] * sum3(t);
      moment_y[i] = weight[0][i] * moment3(t);
    }
    v[0] = sum3(sum);
    Bo[0][0] = moment3(sum);
    Bo[1][0] = sum3(moment_y);
  } else {
#pragma GCC unroll 2
    for (int l = 0; l < P; ++l) {
      Pair sum[3], moment_y[3], moment_z[3];  // per i, over its 3×3 nodes, weighted
#pragma GCC unroll 3
      for (int i = 0; i < 3; ++i) {
        Pair row_sum[3], row_moment_z[3];  // per (i, j), over its 3 nodes, weighted
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j) {
          const double* node = grid + 4 * (row + i * stride[0] + j * stride[1]) + 2 * l;
          Pair t[3];
#pragma GCC unroll 3
          for (int k = 0; k < 3; ++k) t[k] = weight[2][k] * load(node + 4 * k);
          row_sum[j] = weight[1][j] * sum3(t);
          row_moment_z[j] = weight[1][j] * moment3(t);
        }
        sum[i] = weight[0][i] * sum3(row_sum);
        moment_y[i] = weight[0][i] * moment3(row_sum);
        moment_z[i] = weight[0][i] * sum3(row_moment_z);
      }
      v[l] = sum3(sum);
      Bo[0][l] = moment3(sum);
      Bo[1][l] = sum3(moment_y);
      Bo[2][l] = sum3(moment_z);
    }
  }
  for (int r = 0; r < D; ++r) {
    v_out[r] = v[r / 2][r % 2];
    for (int c = 0; c < D; ++c) Bo_out(r, c) = Bo[c][r / 2][r % 2];
  }
}

std::string shortest(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// How many particles ahead the 2D scatter asks for a particle's inputs (measured
// when the 3D scatter read them this way too: 2, 4, 8 and 16 ahead; 8 was the
// fastest).
constexpr int kPrefetchAhead = 8;

// Asks the caches for what the scatter will read of particle p.
template <int D, typename Mat>
void prefetch_scatter_inputs(const Particles<D>& ps, const std::vector<Mat>& affine, int p) {
  const auto* a = reinterpret_cast<const char*>(&affine[static_cast<std::size_t>(p)]);
  __builtin_prefetch(&ps.x[p]);
  __builtin_prefetch(&ps.v[p]);
  __builtin_prefetch(&ps.mass[p]);
  __builtin_prefetch(a);
  __builtin_prefetch(a + sizeof(Mat) - 1);  // the matrix may span two lines
}

// Copies `from` to `to` past the caches, whole lines at a time (`to` is
// line-aligned and its size a multiple of 64 bytes): nothing is read of `to`'s
// lines first, and the copies do not evict what the caller works on. The writing
// thread calls _mm_sfence before another thread reads them.
template <typename T>
void stream_store(const T& from, T& to) {
  static_assert(sizeof(T) % 64 == 0 && alignof(T) % 64 == 0);
  const auto* f = reinterpret_cast<const double*>(&from);
  auto* t = reinterpret_cast<double*>(&to);
  for (std::size_t i = 0; i < sizeof(T) / sizeof(double); i += 2) _mm_stream_pd(t + i, _mm_load_pd(f + i));
}

// Every array of `from` into `to` in another order: to[slot[p]] = from[p], or, to
// put them back, to[p] = from[slot[p]] (slot a permutation of the indices).
enum class Direction { to_slots, back };
template <int D>
void permute(const Particles<D>& from, Particles<D>& to, const std::vector<int>& slot, Direction direction) {
  const int n = from.size();
  Particles<D>::each_array([&](auto array) {
    const auto& src = from.*array;
    auto& dst = to.*array;
    dst.resize(src.size());
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& r) {
      for (int p = r.begin(); p < r.end(); ++p) {
        const auto s = static_cast<std::size_t>(slot[static_cast<std::size_t>(p)]);
        if (direction == Direction::to_slots)
          dst[s] = src[static_cast<std::size_t>(p)];
        else
          dst[static_cast<std::size_t>(p)] = src[s];
      }
    });
  });
}

double sound_speed_squared(Material m, double mu, double lambda, double J, double rho) {
  double stiffness = lambda + 2 * mu;
  if (m == Material::snow) stiffness *= snow_hardening(J);
  return stiffness / rho;
}

// The largest |v| + c over particles, c = √c² the sound speed. c depends on a
// particle's constants alone (material, μ, λ, mass, volume), except for snow's (J
// too), and neighbours in memory usually share them: over a run of particles with
// one c the largest is √(max |v|²) + c exactly, since √ and + round monotonically,
// so the division and both square roots are taken once a run, not once a particle
// (G2P's stalls on them were measured in docs/mpm.md).
class LargestSignalSpeed {
 public:
  explicit LargestSignalSpeed(double best) : best_(best) {}
  // A particle's constants, its J and |v|². (A NaN |v|² or c is passed over, as
  // std::max(best, NaN) passes over it.)
  void add(Material m, double mu, double lambda, double J, double mass, double volume, double v2) {
    if (!(open_ && m == material_ && m != Material::snow && mu == mu_ && lambda == lambda_ && mass == mass_ &&
          volume == volume_)) {
      close();
      open_ = true;
      material_ = m, mu_ = mu, lambda_ = lambda, mass_ = mass, volume_ = volume;
      c_ = std::sqrt(sound_speed_squared(m, mu, lambda, J, mass / volume));
      v2_ = -1;  // none yet
    }
    if (v2 > v2_) v2_ = v2;
  }
  double largest() {
    close();
    return best_;
  }

 private:
  void close() {
    if (open_ && v2_ >= 0) best_ = std::max(best_, std::sqrt(v2_) + c_);
    open_ = false;
  }
  double best_;
  bool open_ = false;
  Material material_{};
  double mu_ = 0, lambda_ = 0, mass_ = 0, volume_ = 0, c_ = 0, v2_ = -1;
};

}  // namespace

template <int D>
Solver<D>::Solver(const Settings& settings)
    : s_(settings), n_(settings.resolution), dx_(settings.size / settings.resolution),
      inv_dx_(settings.resolution / settings.size) {
  if (n_ < 8) throw Error("resolution must be at least 8 cells");
  if (!(s_.size > 0)) throw Error("domain size must be positive");
  if (!(s_.cfl > 0) || !(s_.dt_max > 0)) throw Error("cfl and dt_max must be positive");
  long cells = 1;
  for (int d = D - 1; d >= 0; --d) stride_[d] = cells, cells *= n_;
  grid_.assign(static_cast<std::size_t>(cells), Node::Zero());
  blocks_per_axis_ = (n_ + kBlockCells - 1) / kBlockCells;
  int blocks = 1;
  for (int d = 0; d < D; ++d) blocks *= blocks_per_axis_;
  block_start_.assign(static_cast<std::size_t>(blocks) + 1, 0);
  for (auto& list : colour_blocks_) list.reserve(static_cast<std::size_t>(blocks));
  reachable_.assign(static_cast<std::size_t>(blocks), 0);
  reachable_before_.assign(static_cast<std::size_t>(blocks), 0);
}

template <int D>
double Solver<D>::cfl_dt(double signal_speed) const {
  return signal_speed > 0 ? std::min(s_.dt_max, s_.cfl * dx_ / signal_speed) : s_.dt_max;
}

template <int D>
long Solver<D>::clamp_positions(Particles<D>& ps) const {
  const double lo = 2 * dx_, hi = s_.size - 2 * dx_;
  long moved = 0;
  for (auto& x : ps.x) {
    bool out = false;
    for (int d = 0; d < D; ++d) {
      if (!(x[d] >= lo)) x[d] = lo, out = true;  // also catches NaN
      if (x[d] > hi) x[d] = hi, out = true;
    }
    moved += out;
  }
  return moved;
}

template <int D>
double Solver<D>::max_signal_speed(const Particles<D>& ps) const {
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, ps.size(), 4096), 0.0,
      [&](const tbb::blocked_range<int>& r, double best) {
        LargestSignalSpeed speed(best);
        for (int p = r.begin(); p < r.end(); ++p)
          speed.add(ps.material[p], ps.mu[p], ps.lambda[p], ps.J[p], ps.mass[p], ps.volume[p], ps.v[p].squaredNorm());
        return speed.largest();
      },
      [](double a, double b) { return std::max(a, b); });
}

template <int D>
void Solver<D>::bin(const Particles<D>& ps) {
  constexpr int B = kBlockCells;
  const int np = ps.size();
  const int blocks = static_cast<int>(block_start_.size()) - 1;
  block_of_.resize(static_cast<std::size_t>(np));  // allocates only when the count grows
  (kBlockOrderedInputs ? slot_ : order_).resize(static_cast<std::size_t>(np));
  // Counting sort, stable: each block's particles stay in index order. Consecutive
  // chunks of particles are counted and scattered in parallel, each chunk from its
  // own cursors, which start where the earlier chunks' particles of the block end;
  // the result is the one stable order, whatever the number of chunks.
  const int threads = static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  const int chunks = std::clamp(np / 2048, 1, threads);
  cursor_.assign(static_cast<std::size_t>(chunks) * blocks, 0);
  const auto each_chunk = [&](const auto& body) {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, chunks, 1),
        [&](const tbb::blocked_range<int>& r) {
          for (int c = r.begin(); c < r.end(); ++c)
            body(&cursor_[static_cast<std::size_t>(c) * blocks], static_cast<int>(long(np) * c / chunks),
                 static_cast<int>(long(np) * (c + 1) / chunks));
        },
        tbb::simple_partitioner());
  };
  // Both passes go by runs of particles in one block, which advance() makes long
  // (its particles are in block order): a block's count and cursor are kept in a
  // register over its run, not incremented in memory particle after particle, each
  // increment waiting for the one before.
  each_chunk([&](int* count, int begin, int end) {
    int run_block = -1, run = 0;
    for (int p = begin; p < end; ++p) {
      int block = 0;
      for (int d = 0; d < D; ++d)
        block = block * blocks_per_axis_ + static_cast<int>(ps.x[p][d] * inv_dx_ - 0.5) / B;
      block_of_[p] = block;
      if (block == run_block) {
        ++run;
      } else {
        if (run) count[run_block] += run;
        run_block = block, run = 1;
      }
    }
    if (run) count[run_block] += run;
  });
  int start = 0;  // counts become cursors: block by block, chunk by chunk
  for (int b = 0; b < blocks; ++b) {
    block_start_[b] = start;
    for (int c = 0; c < chunks; ++c) {
      int& cursor = cursor_[static_cast<std::size_t>(c) * blocks + b];
      start += std::exchange(cursor, start);
    }
  }
  block_start_[blocks] = start;
  for (auto& list : colour_blocks_) list.clear();
  for (int b = 0; b < blocks; ++b) {
    if (block_start_[b + 1] == block_start_[b]) continue;
    const std::array<int, D> c = block_coordinates(b);
    int colour = 0;
    for (int d = 0; d < D; ++d) colour |= (c[d] & 1) << d;
    colour_blocks_[colour].push_back(b);
  }
  each_chunk([&](int* cursor, int begin, int end) {
    int run_block = -1, next = 0;  // the run's block and its next place
    for (int p = begin; p < end; ++p) {
      const int block = block_of_[p];
      if (block != run_block) {
        if (run_block >= 0) cursor[run_block] = next;
        run_block = block, next = cursor[block];
      }
      const int place = next++;
      if constexpr (kBlockOrderedInputs)
        slot_[p] = place;
      else
        order_[place] = p;
    }
    if (run_block >= 0) cursor[run_block] = next;
  });
  mark_reachable_blocks();
}

// A particle of block b has its stencil's lowest node in b and its highest two
// nodes further along each axis, so its nodes lie in b and the blocks one further
// along any set of axes (B ≥ 2). Those are this substep's reachable blocks; the
// clear takes them and last substep's (whose nodes may hold last substep's sums),
// the grid update this substep's. Every node outside both was zero and stays so,
// as the clear of every node would leave it.
template <int D>
std::array<int, D> Solver<D>::block_coordinates(int b) const {
  std::array<int, D> c;
  for (int d = D - 1; d >= 0; --d, b /= blocks_per_axis_) c[static_cast<std::size_t>(d)] = b % blocks_per_axis_;
  return c;
}

template <int D>
void Solver<D>::mark_reachable_blocks() {
  reachable_before_.swap(reachable_);
  std::fill(reachable_.begin(), reachable_.end(), 0);
  const int blocks = static_cast<int>(reachable_.size());
  for (int b = 0; b < blocks; ++b) {
    if (block_start_[b + 1] == block_start_[b]) continue;
    const std::array<int, D> c = block_coordinates(b);
    for (int corner = 0; corner < (1 << D); ++corner) {
      int next = 0;
      bool inside = true;
      for (int d = 0; d < D; ++d) {
        const int cd = c[d] + ((corner >> d) & 1);
        inside = inside && cd < blocks_per_axis_;
        next = next * blocks_per_axis_ + cd;
      }
      if (inside) reachable_[static_cast<std::size_t>(next)] = 1;
    }
  }
  to_clear_.clear();
  to_update_.clear();
  for (int b = 0; b < blocks; ++b) {
    if (reachable_[b] || reachable_before_[b]) to_clear_.push_back(b);
    if (reachable_[b]) to_update_.push_back(b);
  }
}

template <int D>
long Solver<D>::reachable_nodes() const {
  constexpr int B = kBlockCells;
  long nodes = 0;
  for (const int b : to_update_) {
    const std::array<int, D> c = block_coordinates(b);
    long box = 1;
    for (int d = 0; d < D; ++d) box *= std::min(B, n_ - c[d] * B);
    nodes += box;
  }
  return nodes;
}

// Calls f(i) for the index i of every node of the given blocks (each a B^D box of
// nodes, cut at the grid's end), the blocks in parallel: they share no node.
template <int D>
template <typename F>
void Solver<D>::for_nodes_of_blocks(const std::vector<int>& blocks, const F& f) {
  constexpr int B = kBlockCells;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, blocks.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const std::array<int, D> c = block_coordinates(blocks[k]);
          int lo[D], hi[D];
          for (int d = 0; d < D; ++d) lo[d] = c[d] * B, hi[d] = std::min(lo[d] + B, n_);
          if constexpr (D == 2) {
            for (int x = lo[0]; x < hi[0]; ++x)
              for (long i = x * stride_[0] + lo[1]; i < x * stride_[0] + hi[1]; ++i) f(i);
          } else {
            for (int x = lo[0]; x < hi[0]; ++x)
              for (int y = lo[1]; y < hi[1]; ++y)
                for (long i = x * stride_[0] + y * stride_[1] + lo[2]; i < x * stride_[0] + y * stride_[1] + hi[2]; ++i)
                  f(i);
          }
        }
      });
}

template <int D>
void Solver<D>::p2g(Particles<D>& ps, double dt) {
  for_nodes_of_blocks(to_clear_, [&](long i) { grid_[static_cast<std::size_t>(i)].setZero(); });
  // The stress first, in a pass of its own over the particles in index order: it
  // touches no node, so its iterations are independent and short, and the core
  // overlaps one particle's chain of dependent operations (the polar iteration's,
  // the SVD's) with the next. In 2D the fluid's stress, a product, is left to the
  // scatter: there the pass would cost more in memory traffic than it gains
  // (measured in docs/mpm.md). In 3D the pass also writes the scatter's inputs.
  constexpr bool kFluidStressInScatter = D == 2;
  // MLS-MPM's affine momentum: −Δt V⁰ 4/Δx² τ + m C  (Hu 2018, eq. 29).
  const double stress_scale = -dt * 4 * inv_dx_ * inv_dx_;
  const auto affine_momentum = [&](int p, const Mat& tau) -> Mat {
    return (stress_scale * ps.volume[p]) * tau + ps.mass[p] * ps.C[p];
  };
  // (Each container allocates only when the count grows.)
  if constexpr (kBlockOrderedInputs)
    scatter_inputs_.resize(static_cast<std::size_t>(ps.size()));
  else
    affine_.resize(static_cast<std::size_t>(ps.size()));
  // In 3D each particle's scatter inputs go to its place in block order, written
  // past the caches (the writes land all over the array; the scatter reads them
  // back in a stream).
  const auto store_input = [&](int p, const Mat& tau) {
    const Mat affine = affine_momentum(p, tau);
    if constexpr (kBlockOrderedInputs) {
      ScatterInput in;
      in.x = ps.x[p];
      in.v = ps.v[p];
      in.mass = ps.mass[p];
      in.affine = affine;
      stream_store(in, scatter_inputs_[static_cast<std::size_t>(slot_[p])]);
    } else {
      affine_[static_cast<std::size_t>(p)] = affine;
    }
  };
  // In 3D particles go two at a time (kirchhoff_stresses: the same stresses as one
  // at a time, so how the range is split does not matter).
  tbb::parallel_for(tbb::blocked_range<int>(0, ps.size(), 1024), [&](const tbb::blocked_range<int>& r) {
    long clamped = 0;
    if constexpr (kFluidStressInScatter) {
      for (int p = r.begin(); p < r.end(); ++p) {
        if (ps.material[p] == Material::fluid) continue;
        Mat tau;
        clamped += kirchhoff_stress(ps, p, tau);
        store_input(p, tau);
      }
    } else {
      int p = r.begin();
      for (; p + 1 < r.end(); p += 2) {
        Mat tau[2];
        clamped += kirchhoff_stresses(ps, p, tau);
        store_input(p, tau[0]);
        store_input(p + 1, tau[1]);
      }
      if (p < r.end()) {
        Mat tau;
        clamped += kirchhoff_stress(ps, p, tau);
        store_input(p, tau);
      }
    }
    if (clamped) clamped_ += clamped;
    if constexpr (kBlockOrderedInputs) _mm_sfence();
  });
  // Σ_i w_i (m v + affine (x_i − x_p)) with x_i − x_p = (o − fx) Δx, split as
  // q + A o: q = m v − affine fx Δx, A = affine Δx. (always_inline: GCC 12 called
  // it in 3D, 16 instructions a particle more.)
  const auto scatter_particle = [&](const Vec& x, const Vec& v, double m, const Mat& affine)
      __attribute__((always_inline)) {
    const Weights<D> w(x, inv_dx_);
    const Vec q = m * v - affine * (w.fx * dx_);
    const Mat A = affine * dx_;
    long base = 0;
    for (int d = 0; d < D; ++d) base += w.base[d] * stride_[d];
    scatter<D>(grid_.data()->data(), base, stride_.data(), w, q, A, m);
  };
  // In 2D the scatter reads the particles' arrays out of index order: x, v, mass
  // and affine matrix are cache misses, which it asks for ahead. (GCC 12 dropped
  // the same prefetches written in a lambda here.)
  const int end = ps.size();
  for (const auto& blocks : colour_blocks_) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k < r.end(); ++k) {
        const int b = blocks[k];
        for (int i = block_start_[b]; i < block_start_[b + 1]; ++i) {
          if constexpr (kBlockOrderedInputs) {
            const ScatterInput& in = scatter_inputs_[static_cast<std::size_t>(i)];
            scatter_particle(in.x, in.v, in.mass, in.affine);
          } else {
            if (i + kPrefetchAhead < end) prefetch_scatter_inputs(ps, affine_, order_[i + kPrefetchAhead]);
            const int p = order_[i];
            const bool fluid = kFluidStressInScatter && ps.material[p] == Material::fluid;
            scatter_particle(
                ps.x[p], ps.v[p], ps.mass[p],
                fluid ? affine_momentum(p, fluid_kirchhoff_stress(ps, p)) : affine_[static_cast<std::size_t>(p)]);
          }
        }
      }
    });
  }
}

template <int D>
void Solver<D>::grid_update(double dt) {
  const Vec g = s_.gravity.template head<D>();
  const int wall = s_.walls_enabled ? s_.wall_cells : 0;
  auto apply = [](Vec& v, const Vec& n, Boundary bc) {
    if (bc == Boundary::sticky) {
      v.setZero();
    } else {
      const double vn = v.dot(n);
      if (bc == Boundary::slip || vn < 0) v -= vn * n;
    }
  };
  for_nodes_of_blocks(to_update_, [&](long i) {
    Node& node = grid_[static_cast<std::size_t>(i)];
    if (node[D] <= 0) return;
    Vec v = node.template head<D>() / node[D] + dt * g;
    Eigen::Matrix<int, D, 1> idx;
    for (int d = 0, r2 = static_cast<int>(i); d < D; ++d) idx[D - 1 - d] = r2 % n_, r2 /= n_;
    for (int d = 0; d < D; ++d) {
      if (idx[d] < wall) apply(v, Vec::Unit(d), s_.walls);
      if (idx[d] > n_ - 1 - wall) apply(v, -Vec::Unit(d), s_.walls);
    }
    if (!s_.colliders.empty()) {
      const Vec x = idx.template cast<double>() * dx_;
      for (const Collider& c : s_.colliders) {
        const Vec point = c.point.template head<D>();
        if (c.shape == Collider::Shape::plane) {
          const Vec n = c.normal.template head<D>().normalized();
          if ((x - point).dot(n) < 0) apply(v, n, c.boundary);
        } else {
          const Vec r = x - point;
          const double dist = r.norm();
          if (dist < c.radius && dist > 0) apply(v, r / dist, c.boundary);
        }
      }
    }
    node.template head<D>() = v;
  });
}

template <int D>
double Solver<D>::g2p(Particles<D>& ps, double dt) {
  const double lo = 2 * dx_, hi = s_.size - 2 * dx_;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, ps.size(), 1024), 0.0,
      [&](const tbb::blocked_range<int>& r, double best) {
        long clamped = 0;
        LargestSignalSpeed speed(best);
        for (int p = r.begin(); p < r.end(); ++p) {
          const Weights<D> w(ps.x[p], inv_dx_);
          // v = Σ w_i v_i and B = Σ w_i v_i (x_i − x_p)ᵀ = (Σ w_i v_i oᵀ − v fxᵀ) Δx.
          Vec v;
          Mat Bo;
          long base = 0;
          for (int d = 0; d < D; ++d) base += w.base[d] * stride_[d];
          gather<D>(grid_.data()->data(), base, stride_.data(), w, v, Bo);
          const Mat B = (Bo - v * w.fx.transpose()) * dx_;
          // APIC: C = 4/Δx² Σ w v_i (x_i − x_p)ᵀ for quadratic B-splines.
          const Mat C = (4 * inv_dx_ * inv_dx_) * B;
          if (!v.allFinite() || !C.allFinite()) {  // the step blew up: advance() stops
            diverged_ = true;
            continue;
          }
          ps.v[p] = v;
          ps.C[p] = C;
          // (Clamped as a vector: written a component at a time, GCC stored both to
          // the stack and loaded them back as one pair, a store-forwarding stall.)
          ps.x[p] = (ps.x[p] + dt * v).cwiseMax(lo).cwiseMin(hi);
          if (ps.material[p] == Material::fluid) {
            double J = ps.J[p] * (1 + dt * C.trace());  // mpm88
            if (!(J >= kMinJ)) J = kMinJ, ++clamped;
            ps.J[p] = J;
          } else {
            ps.F[p] = (Mat::Identity() + dt * C) * ps.F[p];
            clamped += plastic_projection(ps, p, s_.sand);
          }
          speed.add(ps.material[p], ps.mu[p], ps.lambda[p], ps.J[p], ps.mass[p], ps.volume[p], v.squaredNorm());
        }
        if (clamped) clamped_ += clamped;
        return speed.largest();
      },
      [](double a, double b) { return std::max(a, b); });
}

template <int D>
double Solver<D>::substep(Particles<D>& ps, double dt) {
  bin(ps);
  p2g(ps, dt);
  grid_update(dt);
  return g2p(ps, dt);
}

template <int D>
std::vector<int> Solver<D>::block_order_slots(const Particles<D>& ps) {
  bin(ps);
  std::vector<int> slot(static_cast<std::size_t>(ps.size()));
  if constexpr (kBlockOrderedInputs)
    slot = slot_;
  else
    for (int i = 0; i < ps.size(); ++i) slot[static_cast<std::size_t>(order_[i])] = i;
  return slot;
}

template <int D>
Particles<D> Solver<D>::in_block_order(const Particles<D>& ps) {
  Particles<D> sorted;
  permute(ps, sorted, block_order_slots(ps), Direction::to_slots);
  return sorted;
}

template <int D>
AdvanceReport Solver<D>::advance(Particles<D>& ps, double seconds,
                                 const std::function<void(double)>& between) {
  AdvanceReport report;
  clamped_ = 0;
  diverged_ = false;
  report.clamped_positions = clamp_positions(ps);
  if (!(seconds > 0) || ps.size() == 0) return report;
  double speed = max_signal_speed(ps);
  double t = 0;
  report.dt_min = s_.dt_max;
  // One rule for the start state and every substep: a NaN or infinite
  // velocity (or a particle g2p refused) ends the frame with an error.
  const auto require_finite = [&] {
    if (diverged_ || !std::isfinite(speed))
      throw Error("the simulation diverged at " + shortest(t) + " s into the frame (NaN or infinite "
                  "velocities): lower cfl or dt_max, or the stiffness");
  };
  require_finite();
  // The substeps run on a copy of the particles in block order, put back in the
  // caller's order at the end (an error leaves the caller's particles as they
  // were). G2P reads the grid in storage order, and a simulation mixes the order
  // the emitters left: in a 3D dam break, G2P took 27 % longer after 0.5 s and 47 %
  // after 0.75 s (measured in docs/mpm.md).
  const std::vector<int> slot = block_order_slots(ps);
  Particles<D> sorted;
  permute(ps, sorted, slot, Direction::to_slots);
  while (seconds - t > 1e-12 * seconds) {
    const double remaining = seconds - t;
    const double steps = std::ceil(remaining / cfl_dt(speed) - 1e-9);
    const double dt = remaining / std::max(steps, 1.0);
    if (report.substeps >= s_.max_substeps)
      throw Error("more than " + std::to_string(s_.max_substeps) + " substeps in one frame (Δt " + shortest(dt) +
                  " s): lower the stiffness or the speeds, or raise max_substeps");
    speed = substep(sorted, dt);
    require_finite();
    t += dt;
    ++report.substeps;
    report.dt_min = std::min(report.dt_min, dt);
    report.dt_max = std::max(report.dt_max, dt);
    if (between) between(t / seconds);
  }
  permute(sorted, ps, slot, Direction::back);
  report.clamped_deformation = clamped_.load();
  return report;
}

template class Solver<2>;
template class Solver<3>;

}  // namespace loom::mpm
