#include "loom/builtin_types.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "loom/point_pairs.hpp"

namespace loom {

std::string describe_json(const json& j) {
  std::string text = j.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  const char* kind = j.is_null()              ? "null"
                     : j.is_boolean()         ? "a boolean"
                     : j.is_number_integer()  ? "an integer"
                     : j.is_number()          ? "a number"
                     : j.is_string()          ? "a string"
                     : j.is_array()           ? "an array"
                                              : "an object";
  return text + " (" + kind + ")";
}

namespace {

[[noreturn]] void expected(const char* what, const json& j) {
  throw Error(std::string("expected ") + what + ", got " + describe_json(j));
}

double number(const json& j, const char* what) {
  if (!j.is_number()) expected(what, j);
  double v = j.get<double>();
  if (!std::isfinite(v)) expected(what, j);
  return v;
}

int integer(const json& j, const char* what) {
  bool whole = j.is_number_integer();
  if (j.is_number_unsigned()) {
    if (j.get<unsigned long long>() <= 2147483647ULL) return static_cast<int>(j.get<unsigned long long>());
  } else if (j.is_number_integer()) {
    auto v = j.get<long long>();
    if (v >= -2147483647LL && v <= 2147483647LL) return static_cast<int>(v);
  } else if (j.is_number_float()) {
    double d = j.get<double>();
    whole = std::isfinite(d) && std::floor(d) == d;
    if (whole && std::abs(d) < 2147483647.0) return static_cast<int>(d);
  }
  // A whole number past 32 bits is not "not an integer": say what the limit is.
  if (whole) throw Error(describe_json(j) + " is beyond what an Int holds (-2147483647 to 2147483647)");
  expected(what, j);
}

template <class Vec, class Read>
Vec fixed_vector(const json& j, const char* what, Read read) {
  if (!j.is_array() || j.size() != static_cast<std::size_t>(Vec::RowsAtCompileTime))
    expected(what, j);
  Vec v;
  for (int i = 0; i < Vec::RowsAtCompileTime; ++i) v[i] = read(j[i], what);
  return v;
}

template <class Vec>
json vector_json(const Vec& v) {
  json a = json::array();
  for (int i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

bool TypeTraits<bool>::from_json(const json& j) {
  if (!j.is_boolean()) expected("true or false", j);
  return j.get<bool>();
}
json TypeTraits<bool>::to_json(const bool& v) { return v; }
std::string TypeTraits<bool>::summary(const bool& v) { return v ? "true" : "false"; }

int TypeTraits<int>::from_json(const json& j) { return integer(j, "an integer"); }
json TypeTraits<int>::to_json(const int& v) { return v; }
std::string TypeTraits<int>::summary(const int& v) { return std::to_string(v); }

double TypeTraits<double>::from_json(const json& j) { return number(j, "a number"); }
json TypeTraits<double>::to_json(const double& v) { return v; }
std::string TypeTraits<double>::summary(const double& v) { return fmt(v); }

std::string TypeTraits<std::string>::from_json(const json& j) {
  if (!j.is_string()) expected("a string", j);
  return j.get<std::string>();
}
json TypeTraits<std::string>::to_json(const std::string& v) { return v; }
std::string TypeTraits<std::string>::summary(const std::string& v) { return json(v).dump(); }

Vec2i TypeTraits<Vec2i>::from_json(const json& j) {
  return fixed_vector<Vec2i>(j, "[x, y] with two integers", integer);
}
json TypeTraits<Vec2i>::to_json(const Vec2i& v) { return vector_json(v); }
std::string TypeTraits<Vec2i>::summary(const Vec2i& v) { return to_json(v).dump(); }

Vec2 TypeTraits<Vec2>::from_json(const json& j) {
  return fixed_vector<Vec2>(j, "[x, y] with two numbers", number);
}
json TypeTraits<Vec2>::to_json(const Vec2& v) { return vector_json(v); }
std::string TypeTraits<Vec2>::summary(const Vec2& v) { return to_json(v).dump(); }

Vec3i TypeTraits<Vec3i>::from_json(const json& j) {
  return fixed_vector<Vec3i>(j, "[x, y, z] with three integers", integer);
}
json TypeTraits<Vec3i>::to_json(const Vec3i& v) { return vector_json(v); }
std::string TypeTraits<Vec3i>::summary(const Vec3i& v) { return to_json(v).dump(); }

Vec3 TypeTraits<Vec3>::from_json(const json& j) {
  return fixed_vector<Vec3>(j, "[x, y, z] with three numbers", number);
}
json TypeTraits<Vec3>::to_json(const Vec3& v) { return vector_json(v); }
std::string TypeTraits<Vec3>::summary(const Vec3& v) { return to_json(v).dump(); }

constexpr double kColorLimit = 1e6;

Color TypeTraits<Color>::from_json(const json& j) {
  const char* what = "a color: [r, g, b], [r, g, b, a] or \"#rrggbb[aa]\"";
  Color c;
  if (j.is_string()) {
    std::string s = j.get<std::string>();
    if ((s.size() != 7 && s.size() != 9) || s[0] != '#') expected(what, j);
    for (std::size_t k = 0; k + 1 < s.size(); k += 2) {
      unsigned v = 0;
      if (std::sscanf(s.c_str() + 1 + k, "%2x", &v) != 1) expected(what, j);
      c.rgba[static_cast<int>(k / 2)] = v / 255.0;
    }
    return c;
  }
  if (!j.is_array() || (j.size() != 3 && j.size() != 4)) expected(what, j);
  for (std::size_t k = 0; k < j.size(); ++k) {
    const double v = number(j[k], what);
    // Colors become float pixels and are scaled by intensities up to 1e12:
    // a bound keeps every product finite (HDR emission needs far less).
    if (std::abs(v) > kColorLimit)
      throw Error("expected color components between -" + fmt(kColorLimit) + " and " + fmt(kColorLimit) + ", got " +
                  describe_json(j));
    c.rgba[static_cast<int>(k)] = v;
  }
  return c;
}
json TypeTraits<Color>::to_json(const Color& v) { return vector_json(v.rgba); }
std::string TypeTraits<Color>::summary(const Color& v) { return to_json(v).dump(); }

namespace {
template <class T, class Read>
std::vector<T> list(const json& j, const char* what, Read read) {
  if (!j.is_array()) expected(what, j);
  std::vector<T> out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    try {
      out.push_back(read(j[i]));
    } catch (const Error& e) {
      throw Error("item " + std::to_string(i) + ": " + e.what());
    }
  }
  return out;
}
// "FloatList of 12: [0.5, 1, 2, ...]": the length and the first values.
template <class T>
std::string list_summary(const std::vector<T>& v, const char* name) {
  constexpr std::size_t kShown = 6;
  std::string text = std::string(name) + " of " + std::to_string(v.size()) + ": [";
  for (std::size_t i = 0; i < std::min(v.size(), kShown); ++i)
    text += (i == 0 ? "" : ", ") + TypeTraits<T>::summary(v[i]);
  return text + (v.size() > kShown ? ", ...]" : "]");
}
}  // namespace

std::vector<int> TypeTraits<std::vector<int>>::from_json(const json& j) {
  return list<int>(j, "a list of integers", [](const json& x) { return integer(x, "an integer"); });
}
json TypeTraits<std::vector<int>>::to_json(const std::vector<int>& v) { return v; }
std::string TypeTraits<std::vector<int>>::summary(const std::vector<int>& v) {
  return list_summary(v, "IntList");
}

std::vector<double> TypeTraits<std::vector<double>>::from_json(const json& j) {
  return list<double>(j, "a list of numbers", [](const json& x) { return number(x, "a number"); });
}
json TypeTraits<std::vector<double>>::to_json(const std::vector<double>& v) { return v; }
std::string TypeTraits<std::vector<double>>::summary(const std::vector<double>& v) {
  return list_summary(v, "FloatList");
}

std::vector<std::string> TypeTraits<std::vector<std::string>>::from_json(const json& j) {
  return list<std::string>(j, "a list of strings",
                           [](const json& x) { return TypeTraits<std::string>::from_json(x); });
}
json TypeTraits<std::vector<std::string>>::to_json(const std::vector<std::string>& v) { return v; }
std::string TypeTraits<std::vector<std::string>>::summary(const std::vector<std::string>& v) {
  return list_summary(v, "StringList");
}

std::vector<Vec2> TypeTraits<std::vector<Vec2>>::from_json(const json& j) {
  return list<Vec2>(j, "a list of [x, y] points", TypeTraits<Vec2>::from_json);
}
json TypeTraits<std::vector<Vec2>>::to_json(const std::vector<Vec2>& v) {
  json a = json::array();
  for (const auto& p : v) a.push_back(vector_json(p));
  return a;
}
std::string TypeTraits<std::vector<Vec2>>::summary(const std::vector<Vec2>& v) {
  return list_summary(v, "Vec2List");
}

std::vector<Vec3> TypeTraits<std::vector<Vec3>>::from_json(const json& j) {
  return list<Vec3>(j, "a list of [x, y, z] points", TypeTraits<Vec3>::from_json);
}
json TypeTraits<std::vector<Vec3>>::to_json(const std::vector<Vec3>& v) {
  json a = json::array();
  for (const auto& p : v) a.push_back(vector_json(p));
  return a;
}
std::string TypeTraits<std::vector<Vec3>>::summary(const std::vector<Vec3>& v) {
  return list_summary(v, "Vec3List");
}

json TypeTraits<json>::from_json(const json& j) { return j; }
json TypeTraits<json>::to_json(const json& v) { return v; }
std::string TypeTraits<json>::summary(const json& v) {
  std::string s = v.dump();
  return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

const TypeInfo& enum_type() {
  static const TypeInfo& info =
      register_alias("Enum", "one of a fixed set of strings", type_of<std::string>());
  return info;
}

PointPairs TypeTraits<PointPairs>::from_json(const json& j) {
  const char* what = "point pairs: [[px, py, qx, qy], ...] or [{\"p\": [x, y], \"q\": [x, y]}, ...]";
  if (!j.is_array()) expected(what, j);
  PointPairs pairs;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const json& e = j[i];
    try {
      if (e.is_object()) {
        if (!e.contains("p") || !e.contains("q")) expected("{\"p\": [x, y], \"q\": [x, y]}", e);
        pairs.p.push_back(TypeTraits<Vec2>::from_json(e["p"]));
        pairs.q.push_back(TypeTraits<Vec2>::from_json(e["q"]));
      } else {
        if (!e.is_array() || e.size() != 4) expected("[px, py, qx, qy]", e);
        pairs.p.emplace_back(number(e[0], "a number"), number(e[1], "a number"));
        pairs.q.emplace_back(number(e[2], "a number"), number(e[3], "a number"));
      }
    } catch (const Error& err) {
      throw Error("pair " + std::to_string(i) + ": " + err.what());
    }
  }
  return pairs;
}
json TypeTraits<PointPairs>::to_json(const PointPairs& v) {
  json a = json::array();
  for (std::size_t i = 0; i < v.size(); ++i) a.push_back({v.p[i].x(), v.p[i].y(), v.q[i].x(), v.q[i].y()});
  return a;
}
std::string TypeTraits<PointPairs>::summary(const PointPairs& v) {
  return "PointPairs of " + std::to_string(v.size());
}

// Serialization for the persistent cache: PODs as they are in memory, fixed
// vectors as their coefficients, lists prefixed by their length, Json as CBOR.
namespace {
template <class Vec>
void write_fixed(const Vec& v, ByteWriter& w) {
  w.bytes(v.data(), sizeof(typename Vec::Scalar) * static_cast<std::size_t>(Vec::RowsAtCompileTime));
}
template <class Vec>
Vec read_fixed(ByteReader& r) {
  Vec v;
  r.bytes(v.data(), sizeof(typename Vec::Scalar) * static_cast<std::size_t>(Vec::RowsAtCompileTime));
  return v;
}
template <class Vec>
void write_fixed_list(const std::vector<Vec>& list, ByteWriter& w) {
  w.pod<std::uint64_t>(list.size());
  for (const Vec& v : list) write_fixed(v, w);
}
template <class Vec>
std::vector<Vec> read_fixed_list(ByteReader& r) {
  const auto n = r.pod<std::uint64_t>();
  if (n > r.remaining() / sizeof(Vec)) throw Error("stored value is truncated");
  std::vector<Vec> list(static_cast<std::size_t>(n));
  for (Vec& v : list) v = read_fixed<Vec>(r);
  return list;
}
}  // namespace

void TypeTraits<bool>::write(const bool& v, ByteWriter& w) { w.pod<std::uint8_t>(v ? 1 : 0); }
bool TypeTraits<bool>::read(ByteReader& r) { return r.pod<std::uint8_t>() != 0; }
void TypeTraits<int>::write(const int& v, ByteWriter& w) { w.pod<std::int32_t>(v); }
int TypeTraits<int>::read(ByteReader& r) { return r.pod<std::int32_t>(); }
void TypeTraits<double>::write(const double& v, ByteWriter& w) { w.pod(v); }
double TypeTraits<double>::read(ByteReader& r) { return r.pod<double>(); }
void TypeTraits<std::string>::write(const std::string& v, ByteWriter& w) { w.str(v); }
std::string TypeTraits<std::string>::read(ByteReader& r) { return r.str(); }
void TypeTraits<Vec2i>::write(const Vec2i& v, ByteWriter& w) { write_fixed(v, w); }
Vec2i TypeTraits<Vec2i>::read(ByteReader& r) { return read_fixed<Vec2i>(r); }
void TypeTraits<Vec2>::write(const Vec2& v, ByteWriter& w) { write_fixed(v, w); }
Vec2 TypeTraits<Vec2>::read(ByteReader& r) { return read_fixed<Vec2>(r); }
void TypeTraits<Vec3i>::write(const Vec3i& v, ByteWriter& w) { write_fixed(v, w); }
Vec3i TypeTraits<Vec3i>::read(ByteReader& r) { return read_fixed<Vec3i>(r); }
void TypeTraits<Vec3>::write(const Vec3& v, ByteWriter& w) { write_fixed(v, w); }
Vec3 TypeTraits<Vec3>::read(ByteReader& r) { return read_fixed<Vec3>(r); }
void TypeTraits<Color>::write(const Color& v, ByteWriter& w) { write_fixed(v.rgba, w); }
Color TypeTraits<Color>::read(ByteReader& r) { return Color{read_fixed<Eigen::Vector4d>(r)}; }
void TypeTraits<std::vector<int>>::write(const std::vector<int>& v, ByteWriter& w) { w.vector(v); }
std::vector<int> TypeTraits<std::vector<int>>::read(ByteReader& r) { return r.vector<int>(); }
void TypeTraits<std::vector<double>>::write(const std::vector<double>& v, ByteWriter& w) { w.vector(v); }
std::vector<double> TypeTraits<std::vector<double>>::read(ByteReader& r) { return r.vector<double>(); }
void TypeTraits<std::vector<std::string>>::write(const std::vector<std::string>& v, ByteWriter& w) {
  w.pod<std::uint64_t>(v.size());
  for (const auto& s : v) w.str(s);
}
std::vector<std::string> TypeTraits<std::vector<std::string>>::read(ByteReader& r) {
  const auto n = r.pod<std::uint64_t>();
  if (n > r.remaining() / sizeof(std::uint64_t)) throw Error("stored value is truncated");
  std::vector<std::string> v(static_cast<std::size_t>(n));
  for (auto& s : v) s = r.str();
  return v;
}
void TypeTraits<std::vector<Vec2>>::write(const std::vector<Vec2>& v, ByteWriter& w) { write_fixed_list(v, w); }
std::vector<Vec2> TypeTraits<std::vector<Vec2>>::read(ByteReader& r) { return read_fixed_list<Vec2>(r); }
void TypeTraits<std::vector<Vec3>>::write(const std::vector<Vec3>& v, ByteWriter& w) { write_fixed_list(v, w); }
std::vector<Vec3> TypeTraits<std::vector<Vec3>>::read(ByteReader& r) { return read_fixed_list<Vec3>(r); }
void TypeTraits<json>::write(const json& v, ByteWriter& w) { w.vector(json::to_cbor(v)); }
json TypeTraits<json>::read(ByteReader& r) {
  try {
    return json::from_cbor(r.vector<std::uint8_t>());
  } catch (const json::exception& e) {
    throw Error(std::string("stored JSON is corrupt: ") + e.what());
  }
}
void TypeTraits<PointPairs>::write(const PointPairs& v, ByteWriter& w) {
  write_fixed_list(v.p, w);
  write_fixed_list(v.q, w);
}
PointPairs TypeTraits<PointPairs>::read(ByteReader& r) {
  PointPairs v;
  v.p = read_fixed_list<Vec2>(r);
  v.q = read_fixed_list<Vec2>(r);
  if (v.p.size() != v.q.size()) throw Error("stored point pairs have unequal lengths");
  return v;
}

// Outputs of nodes: no NaN or infinity leaves a node (TypeTraits::check).
namespace {
void require_finite_numbers(bool finite, const char* what) {
  if (!finite) throw Error(std::string(what) + " is NaN or infinite");
}
template <class Vec>
bool all_finite(const std::vector<Vec>& list) {
  return std::all_of(list.begin(), list.end(), [](const Vec& v) { return v.allFinite(); });
}
bool json_finite(const json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_structured())
    return std::all_of(j.begin(), j.end(), [](const json& e) { return json_finite(e); });
  return true;
}
}  // namespace

void TypeTraits<double>::check(const double& v) { require_finite_numbers(std::isfinite(v), "the number"); }
void TypeTraits<Vec2>::check(const Vec2& v) { require_finite_numbers(v.allFinite(), "a component"); }
void TypeTraits<Vec3>::check(const Vec3& v) { require_finite_numbers(v.allFinite(), "a component"); }
void TypeTraits<Color>::check(const Color& v) { require_finite_numbers(v.rgba.allFinite(), "a color component"); }
void TypeTraits<std::vector<double>>::check(const std::vector<double>& v) {
  require_finite_numbers(std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }), "a number in the list");
}
void TypeTraits<std::vector<Vec2>>::check(const std::vector<Vec2>& v) { require_finite_numbers(all_finite(v), "a point in the list"); }
void TypeTraits<std::vector<Vec3>>::check(const std::vector<Vec3>& v) { require_finite_numbers(all_finite(v), "a point in the list"); }
void TypeTraits<json>::check(const json& v) { require_finite_numbers(json_finite(v), "a number in the JSON"); }
void TypeTraits<PointPairs>::check(const PointPairs& v) {
  require_finite_numbers(all_finite(v.p) && all_finite(v.q), "a control point");
}

}  // namespace loom
