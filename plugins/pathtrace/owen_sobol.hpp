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

// Both halves of a 64-bit word reversed and swapped: one reversal turns the
// two scrambled coordinates of a pair back for the price of one.
inline std::uint64_t reverse_bits64(std::uint64_t x) {
  x = __builtin_bswap64(x);
  x = ((x >> 4) & 0x0f0f0f0f0f0f0f0full) | ((x & 0x0f0f0f0f0f0f0f0full) << 4);
  x = ((x >> 2) & 0x3333333333333333ull) | ((x & 0x3333333333333333ull) << 2);
  return ((x >> 1) & 0x5555555555555555ull) | ((x & 0x5555555555555555ull) << 1);
}

// The three scrambles of dimension pair d of one pixel (`pixel_key`: a hash
// of seed and pixel): the index shuffle and one Owen scramble per coordinate.
struct PairSeeds {
  std::uint32_t shuffle, x, y;
};
inline PairSeeds pair_seeds(std::uint64_t pixel_key, std::uint32_t d) {
  const std::uint64_t h = Rng::mix(pixel_key + 0x9e3779b97f4a7c15ull * (d + 1));
  return {std::uint32_t(h), std::uint32_t(h >> 32), std::uint32_t((h * 0xd1342543de82ef95ull) >> 32)};
}

// Point `index` of one pair's sequence as 32-bit fractions, given
// reverse_bits(index) (the same for every pair of a sample). The shuffled
// index i = nested_uniform_scramble(index); Owen scrambling works on reversed
// fractions, and i is van der Corput's reversed fraction, the second
// dimension's is sobol_second_reversed(i).
struct Fractions2 {
  std::uint32_t x, y;
};
inline std::uint32_t shuffled_index(const PairSeeds& s, std::uint32_t reversed_index) {
  return reverse_bits(laine_karras_permutation(reversed_index, s.shuffle));
}
inline Fractions2 owen_sobol_2d(const PairSeeds& s, std::uint32_t reversed_index) {
  const std::uint32_t i = shuffled_index(s, reversed_index);
  const std::uint64_t scrambled_reversed =
      std::uint64_t(laine_karras_permutation(sobol_second_reversed(i), s.y)) << 32 | laine_karras_permutation(i, s.x);
  const std::uint64_t f = reverse_bits64(scrambled_reversed);
  return {std::uint32_t(f >> 32), std::uint32_t(f)};
}
// Its first coordinate alone.
inline std::uint32_t owen_sobol_1d(const PairSeeds& s, std::uint32_t reversed_index) {
  return reverse_bits(laine_karras_permutation(shuffled_index(s, reversed_index), s.x));
}
inline Fractions2 owen_sobol_2d(std::uint64_t pixel_key, std::uint32_t d, std::uint32_t index) {
  return owen_sobol_2d(pair_seeds(pixel_key, d), reverse_bits(index));
}

enum class SamplerKind { sobol, independent };

// The decisions of one bounce; each has its own dimension pair at every
// bounce (a 1D decision takes the first coordinate of its pair).
enum class Decision : std::uint32_t { light, environment_pixel, lobe, direction, roulette };

// The numbers one sample of one pixel draws. `sobol`: pair 0 jitters the
// camera ray, bounce b's decision k takes pair 1 + 5 b + k, so a pair means
// the same decision in every sample of a pixel. The pairs nearly every
// bounce uses (direction; light point when the light sampler reads one, i.e.
// not for a lone point light) are computed when the bounce starts, before
// its ray is traced: a scrambled pair is a chain of ~90 cycles of dependent
// multiplies and bit reversals, which the traversal hides; drawn where they
// are used, they stalled the path loop (16 % of a path's time on the long
// paths of the Embree comparison). Bounces from kSobolBounces on draw from
// the splitmix64 stream instead: their share of the error is small and
// padded high dimensions stratify little.
// `independent`: the splitmix64 stream of Rng(seed, p, s) in the order of the
// draws, decisions ignored.
class PixelSampler {
 public:
  PixelSampler(SamplerKind kind, std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : rng_(seed, pixel, sample),
        pixel_key_(Rng::mix(seed ^ Rng::mix(pixel + 0x632be59bd9b4e019ull))),
        reversed_index_(reverse_bits(std::uint32_t(sample))),
        sobol_(kind == SamplerKind::sobol) {}

  static constexpr std::uint32_t kPairsPerBounce = 5;
  static constexpr int kSobolBounces = 4;

  // Before the first bounce: the camera ray's point in the pixel.
  Vec2f camera_jitter() {
    return sobol_ ? to_floats(owen_sobol_2d(pair_seeds(pixel_key_, 0), reversed_index_)) : rng_.uniform2();
  }

  // `light_point`: whether the bounce will draw a point on a light.
  void start_bounce(int depth, bool light_point) {
    sobol_now_ = sobol_ && depth < kSobolBounces;
    first_pair_ = 1 + std::uint32_t(depth) * kPairsPerBounce;
    light_ready_ = sobol_now_ && light_point;
    if (light_ready_) light_ = sobol_pair(Decision::light);
    if (sobol_now_) direction_ = sobol_pair(Decision::direction);
  }

  float uniform(Decision d) {
    if (!sobol_now_) return rng_.uniform();
    return fraction_to_float(owen_sobol_1d(seeds(d), reversed_index_));
  }
  Vec2f uniform2(Decision d) {
    if (!sobol_now_) return rng_.uniform2();
    if (d == Decision::direction) return direction_;
    return d == Decision::light && light_ready_ ? light_ : sobol_pair(d);
  }

 private:
  static Vec2f to_floats(Fractions2 f) { return {fraction_to_float(f.x), fraction_to_float(f.y)}; }
  PairSeeds seeds(Decision d) const { return pair_seeds(pixel_key_, first_pair_ + std::uint32_t(d)); }
  Vec2f sobol_pair(Decision d) const { return to_floats(owen_sobol_2d(seeds(d), reversed_index_)); }

  Rng rng_;
  std::uint64_t pixel_key_;
  std::uint32_t reversed_index_;
  std::uint32_t first_pair_ = 0;
  bool sobol_, sobol_now_ = false, light_ready_ = false;
  Vec2f light_, direction_;
};

}  // namespace loom::pathtrace
