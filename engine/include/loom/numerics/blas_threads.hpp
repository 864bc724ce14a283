// Plugin author API. OpenBLAS's thread count, for the sparse solvers' BLAS calls. Loom runs BLAS
// on the calling thread (docs/architecture.md, decision 16); benchmarks use
// this to measure what more threads would give.
#pragma once

namespace loom::numerics {

// Sets the loaded OpenBLAS's thread count (looked up at run time: another BLAS
// has no such call and is left alone). Returns false when there is none.
bool set_blas_threads(int threads);

}  // namespace loom::numerics
