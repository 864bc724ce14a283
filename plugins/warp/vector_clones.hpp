// Row kernels marked LOOM_WARP_VECTOR_CLONES are compiled twice on x86-64
// GCC, for the baseline and for AVX2, and the loader picks
// the one the CPU runs (GCC function multiversioning). The kernel sums are
// bound by double-precision sqrt and division, which AVX2 does 4 at a time
// instead of 2: about 2× on the 2-core AMD EPYC of our benchmarks.
// Not under ThreadSanitizer: the clones' resolvers run during relocation,
// before TSan's runtime is initialized, and crash when instrumented.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_THREAD__)
#define LOOM_WARP_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define LOOM_WARP_VECTOR_CLONES
#endif
