#include "loom/numerics/sparse_solver.hpp"
#include "loom/numerics/blas_threads.hpp"

#include <cholmod.h>
#include <dlfcn.h>
#include <umfpack.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "loom/error.hpp"

namespace loom::numerics {
namespace {

void require_square_finite(const SparseMatrix& A, const char* who) {
  if (A.rows() != A.cols())
    throw Error(std::string(who) + ": matrix is " + std::to_string(A.rows()) + " by " +
                std::to_string(A.cols()) + ", expected a square matrix");
  if (A.rows() == 0) throw Error(std::string(who) + ": matrix is empty (0 by 0)");
  // Uncompressed storage may hold gaps between columns: iterate, not scan.
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (!std::isfinite(it.value()))
        throw Error(std::string(who) + ": matrix has a NaN or infinite entry at (" +
                    std::to_string(it.row()) + ", " + std::to_string(it.col()) + ")");
}

void require_rhs_rows(const Eigen::MatrixXd& B, Eigen::Index n, const char* who) {
  if (n < 0) throw Error(std::string(who) + ": solve() called before compute()");
  if (B.rows() != n)
    throw Error(std::string(who) + ": right-hand side has " + std::to_string(B.rows()) +
                " rows, the matrix has " + std::to_string(n));
}

// A view of A's storage as a CHOLMOD matrix, no copy. Uncompressed Eigen
// storage maps to CHOLMOD's unpacked form (per-column counts in nz). The
// lower triangle is used (stype -1), so A may store both triangles.
cholmod_sparse view_lower(const SparseMatrix& A) {
  cholmod_sparse s{};
  s.nrow = static_cast<size_t>(A.rows());
  s.ncol = static_cast<size_t>(A.cols());
  s.nzmax = static_cast<size_t>(A.data().allocatedSize());
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.nz = A.isCompressed() ? nullptr : const_cast<int*>(A.innerNonZeroPtr());
  s.x = const_cast<double*>(A.valuePtr());
  s.z = nullptr;
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;  // Eigen keeps row indices sorted within each column
  s.packed = A.isCompressed() ? 1 : 0;
  return s;
}

cholmod_dense view_dense(const Eigen::MatrixXd& B) {
  cholmod_dense d{};
  d.nrow = static_cast<size_t>(B.rows());
  d.ncol = static_cast<size_t>(B.cols());
  d.nzmax = d.nrow * d.ncol;
  d.d = d.nrow;
  d.x = const_cast<double*>(B.data());
  d.z = nullptr;
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

// OpenBLAS (Debian's BLAS) keeps a pool of threads of its own, outside the
// engine's TBB limit, that spin and sched_yield between the many small BLAS
// calls of a supernodal factorization. On a loaded machine that multiplied a
// 100k-face Tutte map's CPU time by 6 (1.03 s against 0.17 s, same run;
// docs/architecture.md); Loom's parallelism comes from TBB instead. So BLAS
// runs on the calling thread, unless the user set OPENBLAS_NUM_THREADS.
// Looked up at run time in the loaded OpenBLAS (a plugin's libraries may be
// out of the global scope): another BLAS has no such call and is left alone.
// `loom` and `loom-editor` set the variable before anything loads
// (loom/process_start.hpp), so OpenBLAS starts no pool there and this finds
// it set; it is for the other hosts (Python, tests, benchmarks).
void blas_on_calling_thread() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!std::getenv("OPENBLAS_NUM_THREADS")) set_blas_threads(1);
  });
}

// A CHOLMOD workspace set up the same way everywhere: supernodal, silent
// (errors are turned into loom::Error by the caller from Common.status).
struct Common {
  cholmod_common c;
  Common() {
    blas_on_calling_thread();
    cholmod_start(&c);
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.print = 0;
    c.error_handler = nullptr;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

std::string cholmod_failure(const char* step, int status) {
  switch (status) {
    case CHOLMOD_OUT_OF_MEMORY:
      return std::string("sparse Cholesky: out of memory in ") + step;
    case CHOLMOD_TOO_LARGE:
      return std::string("sparse Cholesky: matrix too large for 32-bit indices in ") + step;
    default:
      return std::string("sparse Cholesky: CHOLMOD failed in ") + step + " (status " +
             std::to_string(status) + ")";
  }
}

}  // namespace

// ---------------------------------------------------------------------------

struct SparseCholesky::Impl {
  Common common;
  SparseCholesky::Options options;
  cholmod_factor* L = nullptr;
  Eigen::Index n = -1;
  bool factored = false;
  std::vector<int> outer, inner;  // pattern of the analysed matrix, for refactor()

  ~Impl() {
    if (L) cholmod_free_factor(&L, &common.c);
  }

  void remember_pattern(const SparseMatrix& A) {
    outer.clear();
    inner.clear();
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
      outer.push_back(static_cast<int>(inner.size()));
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        if (it.row() >= j) inner.push_back(static_cast<int>(it.row()));
    }
    outer.push_back(static_cast<int>(inner.size()));
  }

  bool same_pattern(const SparseMatrix& A) const {
    if (A.rows() != n || A.cols() != n) return false;
    std::size_t k = 0;
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
      if (outer[j] != static_cast<int>(k)) return false;
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        if (it.row() >= j) {
          if (k >= inner.size() || inner[k] != it.row()) return false;
          ++k;
        }
    }
    return k == inner.size();
  }

  void analyze(const SparseMatrix& A) {
    if (L) cholmod_free_factor(&L, &common.c);
    factored = false;
    cholmod_sparse s = view_lower(A);
    L = cholmod_analyze(&s, &common.c);
    if (!L) throw Error(cholmod_failure("analysis", common.c.status));
    n = A.rows();
    remember_pattern(A);
  }

  void factorize(const SparseMatrix& A) {
    factored = false;
    cholmod_sparse s = view_lower(A);
    cholmod_factorize(&s, L, &common.c);
    if (common.c.status == CHOLMOD_NOT_POSDEF)
      throw Error("matrix is not positive definite (pivot " + std::to_string(L->minor) + " of " +
                  std::to_string(n) + "): check that the system is symmetric positive definite, "
                  "e.g. that every connected part has a fixed (Dirichlet) value");
    if (common.c.status < CHOLMOD_OK) throw Error(cholmod_failure("factorization", common.c.status));
    // The same numbers, stored column by column (numeric LL', packed).
    if (options.simplicial_solves && !cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, L, &common.c))
      throw Error(cholmod_failure("conversion to simplicial form", common.c.status));
    factored = true;
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::SparseCholesky(const Options& options) : SparseCholesky() { impl_->options = options; }
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::compute(const SparseMatrix& A, const std::function<void()>& check) {
  require_square_finite(A, "sparse Cholesky");
  impl_->analyze(A);
  if (check) check();
  impl_->factorize(A);
}

void SparseCholesky::refactor(const SparseMatrix& A, const std::function<void()>& check) {
  require_square_finite(A, "sparse Cholesky");
  // A simplicial factor cannot be refactored as a supernodal one: analyse again.
  if (!impl_->L || impl_->options.simplicial_solves || !impl_->same_pattern(A)) impl_->analyze(A);
  if (check) check();
  impl_->factorize(A);
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
  require_rhs_rows(B, impl_->factored ? impl_->n : -1, "sparse Cholesky");
  if (B.cols() == 0) return Eigen::MatrixXd(B.rows(), 0);
  // A workspace per call: the factor is only read, so threads may solve at once.
  Common common;
  cholmod_dense b = view_dense(B);
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, impl_->L, &b, &common.c);
  if (!x) throw Error(cholmod_failure("solve", common.c.status));
  Eigen::MatrixXd X = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x),
                                                        B.rows(), B.cols());
  cholmod_free_dense(&x, &common.c);
  return X;
}

int SparseCholesky::rows() const { return static_cast<int>(std::max<Eigen::Index>(impl_->n, 0)); }

const char* SparseCholesky::backend() const { return "cholmod"; }

// ---------------------------------------------------------------------------

// UMFPACK's 64-bit interface (umfpack_dl_*): the 32-bit one counts its
// memory in int and failed "out of memory" (status -1) on Parameterize's
// 2M-vertex system (docs/robustness.md); the indices are copied to 64 bits.
struct SparseLU::Impl {
  SparseMatrix A;  // compressed copy: UMFPACK's iterative refinement reads it
  std::vector<SuiteSparse_long> Ap, Ai;  // A's outer and inner indices, 64-bit
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];

  Impl() {
    blas_on_calling_thread();
    umfpack_dl_defaults(control);
  }
  ~Impl() { release(); }
  void release() {
    if (numeric) umfpack_dl_free_numeric(&numeric);
  }
};

SparseLU::SparseLU() : impl_(std::make_unique<Impl>()) {}
SparseLU::SparseLU(const Options& options) : SparseLU() {
  if (options.refinement_steps < 0)
    throw Error("sparse LU: refinement_steps is " + std::to_string(options.refinement_steps) +
                ", expected 0 (none) or more");
  impl_->control[UMFPACK_IRSTEP] = options.refinement_steps;
}
SparseLU::~SparseLU() = default;
SparseLU::SparseLU(SparseLU&&) noexcept = default;
SparseLU& SparseLU::operator=(SparseLU&&) noexcept = default;

void SparseLU::compute(const SparseMatrix& A, const std::function<void()>& check) {
  require_square_finite(A, "sparse LU");
  Impl& m = *impl_;
  m.release();
  m.A = A;
  m.A.makeCompressed();
  const SuiteSparse_long n = m.A.rows();
  m.Ap.assign(m.A.outerIndexPtr(), m.A.outerIndexPtr() + n + 1);
  m.Ai.assign(m.A.innerIndexPtr(), m.A.innerIndexPtr() + m.A.nonZeros());
  double info[UMFPACK_INFO];
  void* symbolic = nullptr;
  SuiteSparse_long status =
      umfpack_dl_symbolic(n, n, m.Ap.data(), m.Ai.data(), m.A.valuePtr(), &symbolic, m.control, info);
  if (status != UMFPACK_OK) {
    if (symbolic) umfpack_dl_free_symbolic(&symbolic);
    throw Error("sparse LU: UMFPACK analysis failed (status " + std::to_string(status) + ")");
  }
  if (check) {
    try {
      check();
    } catch (...) {
      umfpack_dl_free_symbolic(&symbolic);
      throw;
    }
  }
  status = umfpack_dl_numeric(m.Ap.data(), m.Ai.data(), m.A.valuePtr(), symbolic, &m.numeric, m.control, info);
  umfpack_dl_free_symbolic(&symbolic);
  if (status == UMFPACK_WARNING_singular_matrix) {
    m.release();
    throw Error("matrix is singular: the system has no unique solution (check for rows or "
                "columns without a constraint)");
  }
  if (status != UMFPACK_OK) {
    m.release();
    throw Error("sparse LU: UMFPACK factorization failed (status " + std::to_string(status) + ")");
  }
}

Eigen::MatrixXd SparseLU::solve(const Eigen::MatrixXd& B) const {
  const Impl& m = *impl_;
  require_rhs_rows(B, m.numeric ? m.A.rows() : -1, "sparse LU");
  Eigen::MatrixXd X(B.rows(), B.cols());
  std::atomic<SuiteSparse_long> failed{UMFPACK_OK};
  // umfpack_dl_solve only reads the factors and allocates its own workspace.
  tbb::parallel_for(Eigen::Index(0), B.cols(), [&](Eigen::Index j) {
    double info[UMFPACK_INFO];
    const SuiteSparse_long status = umfpack_dl_solve(UMFPACK_A, m.Ap.data(), m.Ai.data(), m.A.valuePtr(),
                                                     X.col(j).data(), B.col(j).data(), m.numeric, m.control, info);
    if (status != UMFPACK_OK) failed = status;
  });
  if (failed.load() != UMFPACK_OK)
    throw Error("sparse LU: UMFPACK solve failed (status " + std::to_string(failed.load()) + ")");
  return X;
}

const char* SparseLU::backend() const { return "umfpack"; }

bool set_blas_threads(int threads) {
  using SetThreads = void (*)(int);
  void* openblas = dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_NOLOAD);
  void* symbol = dlsym(openblas ? openblas : RTLD_DEFAULT, "openblas_set_num_threads");
  if (symbol) reinterpret_cast<SetThreads>(symbol)(threads);
  if (openblas) dlclose(openblas);
  return symbol != nullptr;
}

}  // namespace loom::numerics
