// Author and host API. Stable 64-bit hashing for computation hashes, cache keys and RNG seeds.
// Stable means: the same bytes give the same hash in every run and build, so
// seeds derived from it reproduce (std::hash promises neither).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace loom {

class Hasher {
 public:
  explicit Hasher(std::uint64_t seed = 0x9e3779b97f4a7c15ull) : h_(seed) {}

  // FNV-1a over the bytes, 8 at a time; finished by a splitmix64 mix.
  Hasher& bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, p + i, 8);
      h_ = (h_ ^ w) * 0x100000001b3ull;
      h_ ^= h_ >> 29;
    }
    for (; i < n; ++i) h_ = (h_ ^ p[i]) * 0x100000001b3ull;
    h_ = (h_ ^ n) * 0x100000001b3ull;  // length, so "ab"+"c" != "a"+"bc"
    return *this;
  }
  Hasher& str(std::string_view s) { return bytes(s.data(), s.size()); }
  template <class T, class = std::enable_if_t<std::is_arithmetic_v<T>>>
  Hasher& pod(T v) { return bytes(&v, sizeof v); }

  std::uint64_t digest() const { return mix(h_); }

  static std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t h_;
};

// Hashes a JSON value by its content (types, keys, values), without printing it.
template <class Json>
void hash_json(Hasher& h, const Json& j) {
  h.pod(static_cast<int>(j.type()));
  if (j.is_object()) {
    h.pod(j.size());
    for (auto it = j.begin(); it != j.end(); ++it) {
      h.str(it.key());
      hash_json(h, it.value());
    }
  } else if (j.is_array()) {
    h.pod(j.size());
    for (const auto& e : j) hash_json(h, e);
  } else if (j.is_string()) {
    h.str(j.template get_ref<const typename Json::string_t&>());
  } else if (j.is_number_float()) {
    h.pod(j.template get<double>());
  } else if (j.is_number_unsigned()) {
    h.pod(j.template get<std::uint64_t>());
  } else if (j.is_number_integer()) {
    h.pod(j.template get<std::int64_t>());
  } else if (j.is_boolean()) {
    h.pod(j.template get<bool>());
  }
}

inline std::uint64_t hash_string(std::string_view s) { return Hasher().str(s).digest(); }

}  // namespace loom
