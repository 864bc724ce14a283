// The core's clock, from a chain of dependent integer adds (one cycle each):
// with an instruction count (callgrind) and a rate it gives the instructions
// per cycle a benchmark sustains, its distance from the compute limit. The
// best of 50 short runs (about 10 ms each), so that the other processes of a
// loaded machine, which can only take time away, drop out.
#pragma once

#include <algorithm>
#include <chrono>

namespace loom::bench {

// The largest of `runs` calls of f (a rate: interruptions only lower it).
template <class F>
double best_of(int runs, const F& f) {
  double best = 0;
  for (int r = 0; r < runs; ++r) best = std::max(best, f());
  return best;
}

// Cycles per second of the calling thread's core, one run (0 where not x86-64).
inline double core_clock_hz_once() {
#if defined(__x86_64__)
  constexpr long iterations = 1'000'000;
  long x = 0;
  const long one = 1;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i) {
    // 20 dependent adds: 20 cycles; the loop's own counter runs beside them.
#define LOOM_ADD4 asm volatile("add %1, %0\n\tadd %1, %0\n\tadd %1, %0\n\tadd %1, %0" : "+r"(x) : "r"(one));
    LOOM_ADD4 LOOM_ADD4 LOOM_ADD4 LOOM_ADD4 LOOM_ADD4
#undef LOOM_ADD4
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return x == 20 * iterations ? 20.0 * iterations / seconds : 0;
#else
  return 0;
#endif
}

// The best of 50 runs.
inline double core_clock_hz() { return best_of(50, core_clock_hz_once); }

}  // namespace loom::bench
