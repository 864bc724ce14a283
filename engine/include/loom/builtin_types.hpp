// Plugin author API. The built-in value types and how they are written in graph files.
//
//   Bool    true            Int     3            Float   0.5
//   String  "text"          Enum    "choice"     (a String checked against choices)
//   Vec2i   [512, 512]      Vec2    [0.5, 1]     Vec3i [1, 2, 3]   Vec3 [0, 0, 1]
//   Color   [r, g, b] or [r, g, b, a] in the image's own encoding, or "#rrggbb[aa]"
//   IntList [1, 2]  FloatList [0.5]  StringList ["a"]  Vec2List [[0, 1], [2, 3]]
//   Vec3List [[0, 0, 1]]    Json    any JSON value (e.g. figures to draw)
//
// Each is storable in the persistent cache (write/read, see loom/serialize.hpp).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "loom/value.hpp"

namespace loom {

using Vec2i = Eigen::Vector2i;
using Vec2 = Eigen::Vector2d;
using Vec3i = Eigen::Vector3i;
using Vec3 = Eigen::Vector3d;
// RGBA; channels past an image's count are ignored.
struct Color {
  Eigen::Vector4d rgba{0, 0, 0, 1};
};

#define LOOM_BUILTIN_TYPE(T, NAME, DESC, ...)                 \
  template <>                                                 \
  struct TypeTraits<T> {                                      \
    static constexpr const char* name = NAME;                 \
    static constexpr const char* description = DESC;          \
    LOOM_API static T from_json(const json& j);               \
    LOOM_API static json to_json(const T& v);                 \
    LOOM_API static std::string summary(const T& v);          \
    static constexpr int version = 1;                         \
    LOOM_API static void write(const T& v, ByteWriter& w);    \
    LOOM_API static T read(ByteReader& r);                    \
    __VA_ARGS__                                               \
  }
// Types holding real numbers refuse NaN and infinities in node outputs.
#define LOOM_REAL_VALUED(T) LOOM_API static void check(const T& v);

LOOM_BUILTIN_TYPE(bool, "Bool", "true or false");
LOOM_BUILTIN_TYPE(int, "Int", "an integer");
LOOM_BUILTIN_TYPE(double, "Float", "a real number", LOOM_REAL_VALUED(double));
LOOM_BUILTIN_TYPE(std::string, "String", "text");
LOOM_BUILTIN_TYPE(Vec2i, "Vec2i", "two integers [x, y]");
LOOM_BUILTIN_TYPE(Vec2, "Vec2", "two numbers [x, y]", LOOM_REAL_VALUED(Vec2));
LOOM_BUILTIN_TYPE(Vec3i, "Vec3i", "three integers [x, y, z]");
LOOM_BUILTIN_TYPE(Vec3, "Vec3", "three numbers [x, y, z]", LOOM_REAL_VALUED(Vec3));
LOOM_BUILTIN_TYPE(Color, "Color", "[r, g, b], [r, g, b, a] or \"#rrggbb\"", LOOM_REAL_VALUED(Color));
LOOM_BUILTIN_TYPE(std::vector<int>, "IntList", "a list of integers");
LOOM_BUILTIN_TYPE(std::vector<double>, "FloatList", "a list of numbers", LOOM_REAL_VALUED(std::vector<double>));
LOOM_BUILTIN_TYPE(std::vector<std::string>, "StringList", "a list of strings");
LOOM_BUILTIN_TYPE(std::vector<Vec2>, "Vec2List", "a list of [x, y] points", LOOM_REAL_VALUED(std::vector<Vec2>));
LOOM_BUILTIN_TYPE(std::vector<Vec3>, "Vec3List", "a list of [x, y, z] points", LOOM_REAL_VALUED(std::vector<Vec3>));
LOOM_BUILTIN_TYPE(json, "Json", "any JSON value", LOOM_REAL_VALUED(json));

#undef LOOM_REAL_VALUED
#undef LOOM_BUILTIN_TYPE

// Any: a wildcard for nodes that pass values through (Switch, Print). Links to
// and from Any are checked when the value arrives, not when the graph loads.
struct Any {};
template <>
struct TypeTraits<Any> {
  static constexpr const char* name = "Any";
  static constexpr const char* description = "a value of any type (checked at run time)";
};
// Types are compared by TypeInfo identity (one TypeInfo per name, see
// register_type), never by their name strings.
inline bool is_any(const TypeInfo& type) { return &type == &type_of<Any>(); }

// The Enum type: a String whose value is one of an input's choices.
LOOM_API const TypeInfo& enum_type();

// Describes a JSON value in an error message: `"abc" (a string)`.
LOOM_API std::string describe_json(const json& j);

}  // namespace loom
