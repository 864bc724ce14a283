// What one core computes per second, as Loom is compiled (x86-64 baseline:
// SSE2, no FMA), for the compute limits of the particle benchmarks:
//   the clock, from a chain of dependent integer adds (one cycle each): with an
//     instruction count (callgrind) and a rate, the instructions per cycle a
//     benchmark sustains;
//   the peak double-precision rate, from independent SSE2 multiply and add
//     chains (enough of them to fill the pipelines);
//   scalar divisions and square roots per second, from independent chains
//     (the divider is not pipelined like the multipliers).
// Each is the best of 200 runs of about 1 ms (shorter than a scheduler's time
// slice), so that the other processes of a loaded machine, which can only take
// time away, drop out.
#pragma once

#include <algorithm>
#include <chrono>

#include <emmintrin.h>

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
  constexpr long iterations = 200'000;
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

// Flops per second, one run: 6 independent multiply chains and 6 add chains of
// two doubles each (two pipes of each, latency 3; 14 of the 16 SSE registers).
inline double core_peak_flops_once() {
  constexpr long iterations = 100'000;
  volatile double runtime_one = 1.0, runtime_zero = 0.0;
  const __m128d m = _mm_set1_pd(runtime_one), c = _mm_set1_pd(runtime_zero);
  __m128d p[6], s[6];
  for (int k = 0; k < 6; ++k) p[k] = _mm_set1_pd(k), s[k] = _mm_set1_pd(k);
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i)
    for (int k = 0; k < 6; ++k) p[k] = _mm_mul_pd(p[k], m), s[k] = _mm_add_pd(s[k], c);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double sum = 0, lanes[2];
  for (int k = 0; k < 6; ++k) _mm_storeu_pd(lanes, _mm_add_pd(p[k], s[k])), sum += lanes[0] + lanes[1];
  return sum == 60 ? 24.0 * iterations / seconds : 0;  // Σ 2·(k + k) over k < 6 = 60
}

// Scalar divisions (sqrt = false) or square roots per second, one run: 8
// independent chains of x = c / x or x = c √x (c = 1.7, x from 1.3: operands
// with full mantissas, no fast path for 1 or exact squares; the multiply adds
// latency, not divider work).
inline double core_divider_rate_once(bool sqrt) {
  constexpr long iterations = 20'000;
  volatile double runtime_c = 1.7, runtime_x = 1.3;
  const __m128d c = _mm_set_sd(runtime_c);
  __m128d x[8];
  for (auto& v : x) v = _mm_set_sd(runtime_x);
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < iterations; ++i)
    for (auto& v : x) v = sqrt ? _mm_mul_sd(c, _mm_sqrt_sd(v, v)) : _mm_div_sd(c, v);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double sum = 0;
  for (const auto& v : x) sum += _mm_cvtsd_f64(v);
  return sum > 8 && sum < 24 ? 8.0 * iterations / seconds : 0;  // each x stays in [1.3, 2.9]
}

// The best of 200 runs of each.
inline double core_clock_hz() { return best_of(200, core_clock_hz_once); }
inline double core_peak_flops() { return best_of(200, core_peak_flops_once); }
inline double core_divisions() {
  return best_of(200, [] { return core_divider_rate_once(false); });
}
inline double core_square_roots() {
  return best_of(200, [] { return core_divider_rate_once(true); });
}

}  // namespace loom::bench
