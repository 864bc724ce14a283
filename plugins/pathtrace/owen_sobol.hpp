// Low-discrepancy samples per pixel: the 2D Sobol (0,2)-sequence, shuffled
// and Owen-scrambled by hashing (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4)), padded: every dimension pair d of pixel p has its
// own shuffle and scrambles, seeded by a hash of (seed, p, d).
//
// Owen scrambling flips digit j of a base-2 fraction by a random function of
// digits 1..j-1; Burley's eq. (listing 3) realises it on the bit-reversed
// value with the Laine-Karras hash, where every bit depends only on itself and
// lower bits. Scrambling the *index* the same way (his "nested uniform
// shuffle") maps each aligned block of 2^k indices onto an aligned block, so
// the first 2^k samples of a pixel in any dimension pair are still a
// (0,k,2)-net: one point in every elementary interval of area 2^-k (tested in
// owen_sobol_test). Sample s of pixel p is a pure function of (seed, p, s).
#pragma once

#include <cstdint>

#include "sampling.hpp"

namespace loom::pathtrace {

inline std::uint32_t reverse_bits(std::uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

// Burley 2020, listing 3 (constants from the paper): a bijection of 32-bit
// words in which bit j depends only on bits 0..j of the input and on the seed.
inline std::uint32_t laine_karras_permutation(std::uint32_t x, std::uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Owen scrambling of a 32-bit fraction (Burley 2020, listing 4).
inline std::uint32_t nested_uniform_scramble(std::uint32_t x, std::uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The second Sobol dimension of index i, bit-reversed. Its generator is
// Pascal's triangle mod 2: digit j of the fraction is the parity of the index
// bits k with j ⊆ k (Lucas' theorem), a superset-sum transform in 5 steps.
// (The first dimension, van der Corput's, is the index itself bit-reversed.)
inline std::uint32_t sobol_second_reversed(std::uint32_t i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  i ^= (i >> 16) & 0x0000ffffu;
  return i;
}

// 32-bit fraction to float in [0, 1): its top 24 bits, exact.
inline float fraction_to_float(std::uint32_t x) { return float(x >> 8) * 0x1p-24f; }

// Point `index` of dimension pair `d`'s sequence for one pixel (`pixel_key`:
// a hash of seed and pixel), as 32-bit fractions.
struct Fractions2 {
  std::uint32_t x, y;
};
inline Fractions2 owen_sobol_2d(std::uint64_t pixel_key, std::uint32_t d, std::uint32_t index) {
  const std::uint64_t h = Rng::mix(pixel_key + 0x9e3779b97f4a7c15ull * (d + 1));
  const std::uint32_t shuffle_seed = std::uint32_t(h), x_seed = std::uint32_t(h >> 32);
  const std::uint32_t y_seed = std::uint32_t((h * 0xd1342543de82ef95ull) >> 32);
  const std::uint32_t i = nested_uniform_scramble(index, shuffle_seed);
  return {reverse_bits(laine_karras_permutation(i, x_seed)),
          reverse_bits(laine_karras_permutation(sobol_second_reversed(i), y_seed))};
}

enum class SamplerKind { sobol, independent };

// The numbers one sample of one pixel draws. `sobol`: each call takes the
// next dimension pair (a 1D draw uses the first coordinate of its own pair);
// the path loop starts every bounce at a fixed dimension (start_bounce) so a
// dimension means the same decision in every sample of a pixel. Bounces from
// kSobolBounces on draw from the splitmix64 stream instead: their share of
// the error is small and padded high dimensions stratify little, while a
// scrambled pair costs ~40 cycles (a third of a path's time on long paths).
// `independent`: the splitmix64 stream of Rng(seed, p, s), dimensions ignored.
class PixelSampler {
 public:
  PixelSampler(SamplerKind kind, std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : rng_(seed, pixel, sample),
        pixel_key_(Rng::mix(seed ^ Rng::mix(pixel + 0x632be59bd9b4e019ull))),
        index_(std::uint32_t(sample)),
        sobol_(kind == SamplerKind::sobol),
        sobol_now_(sobol_) {}

  // Dimension pairs: 1 for the camera, then kPairsPerBounce per bounce.
  static constexpr std::uint32_t kPairsPerBounce = 5;
  static constexpr int kSobolBounces = 4;
  void start_bounce(int depth) {
    pair_ = 1 + std::uint32_t(depth) * kPairsPerBounce;
    sobol_now_ = sobol_ && depth < kSobolBounces;
  }

  float uniform() {
    if (!sobol_now_) return rng_.uniform();
    return fraction_to_float(owen_sobol_2d(pixel_key_, pair_++, index_).x);
  }
  Vec2f uniform2() {
    if (!sobol_now_) return rng_.uniform2();
    const Fractions2 f = owen_sobol_2d(pixel_key_, pair_++, index_);
    return {fraction_to_float(f.x), fraction_to_float(f.y)};
  }

 private:
  Rng rng_;
  std::uint64_t pixel_key_;
  std::uint32_t index_;
  std::uint32_t pair_ = 0;
  bool sobol_, sobol_now_;
};

}  // namespace loom::pathtrace
