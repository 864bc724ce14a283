#include "cholmod_limit.hpp"

#include <cholmod.h>

#include "bench_harness.hpp"
#include "loom/numerics/blas_threads.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

namespace loom::bench {
namespace {

template <class F>
double seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One ordering: `method` < 0 leaves CHOLMOD's default strategy (as Loom runs it).
CholmodTiming time_ordering(Eigen::SparseMatrix<double> A, const char* name, int method, int rhs_columns,
                            int runs) {
  A.makeCompressed();
  cholmod_common c;
  cholmod_start(&c);
  c.supernodal = CHOLMOD_SUPERNODAL;
  c.print = 0;
  if (method >= 0) {
    c.nmethods = 1;
    c.method[0].ordering = method;
    c.postorder = 1;
  }
  cholmod_sparse s{};
  s.nrow = s.ncol = static_cast<size_t>(A.rows());
  s.nzmax = static_cast<size_t>(A.nonZeros());
  s.p = A.outerIndexPtr();
  s.i = A.innerIndexPtr();
  s.x = A.valuePtr();
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  cholmod_dense* b = cholmod_ones(s.nrow, static_cast<size_t>(rhs_columns), CHOLMOD_REAL, &c);
  CholmodTiming t;
  t.ordering = name;
  std::vector<double> analyze, factor, solve;
  cholmod_factor* L = nullptr;
  for (int r = 0; r <= runs; ++r) {  // run 0 warms up
    if (L) cholmod_free_factor(&L, &c);
    const double ta = seconds([&] { L = cholmod_analyze(&s, &c); });
    if (!L) throw std::runtime_error("cholmod_analyze failed");
    t.factor_nonzeros = c.lnz;
    t.flops = c.fl;
    const double tf = seconds([&] { cholmod_factorize(&s, L, &c); });
    if (c.status != CHOLMOD_OK) throw std::runtime_error("cholmod_factorize failed");
    cholmod_dense* x = nullptr;
    const double ts = seconds([&] { x = cholmod_solve(CHOLMOD_A, L, b, &c); });
    cholmod_free_dense(&x, &c);
    if (r == 0) continue;
    analyze.push_back(ta);
    factor.push_back(tf);
    solve.push_back(ts);
  }
  cholmod_free_factor(&L, &c);
  cholmod_free_dense(&b, &c);
  cholmod_finish(&c);
  t.analyze = median(analyze);
  t.factor = median(factor);
  t.solve = median(solve);
  return t;
}

}  // namespace

std::vector<CholmodTiming> cholmod_orderings(const Eigen::SparseMatrix<double>& A, int rhs_columns, int runs) {
  std::vector<CholmodTiming> out;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (const int threads : {1, cores}) {
    if (!numerics::set_blas_threads(threads) && threads > 1) break;
    for (const auto& [name, method] : {std::pair<const char*, int>{"default", -1},
                                       {"amd", CHOLMOD_AMD},
                                       {"metis", CHOLMOD_METIS},
                                       {"nesdis", CHOLMOD_NESDIS}}) {
      out.push_back(time_ordering(A, name, method, rhs_columns, runs));
      out.back().blas_threads = threads;
    }
    if (cores == 1) break;
  }
  numerics::set_blas_threads(1);
  return out;
}

const CholmodTiming& best_factor(const std::vector<CholmodTiming>& timings) {
  return *std::min_element(timings.begin(), timings.end(),
                           [](const CholmodTiming& a, const CholmodTiming& b) { return a.factor < b.factor; });
}

}  // namespace loom::bench
