// Plugin author API. PointPairs: control point pairs p_i -> q_i for warping, in pixel coordinates
// (origin top-left, x right, y down; pixel centers at integer + 0.5).
// In graph files: [[px, py, qx, qy], ...] or [{"p": [x, y], "q": [x, y]}, ...].
#pragma once

#include <vector>

#include "loom/builtin_types.hpp"

namespace loom {

struct PointPairs {
  std::vector<Vec2> p;  // sources
  std::vector<Vec2> q;  // targets, same length
  std::size_t size() const { return p.size(); }
};

template <>
struct TypeTraits<PointPairs> {
  static constexpr const char* name = "PointPairs";
  static constexpr const char* description =
      "control point pairs p→q: [[px, py, qx, qy], ...] or [{\"p\": [x, y], \"q\": [x, y]}, ...]";
  LOOM_API static PointPairs from_json(const json& j);
  LOOM_API static json to_json(const PointPairs& v);
  LOOM_API static std::string summary(const PointPairs& v);
  static constexpr int version = 1;
  LOOM_API static void write(const PointPairs& v, ByteWriter& w);
  LOOM_API static PointPairs read(ByteReader& r);
  LOOM_API static void check(const PointPairs& v);
};

}  // namespace loom
