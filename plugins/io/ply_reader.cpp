// Stanford PLY, ASCII or binary (either byte order): the vertex element's
// x y z, normals (nx ny nz), texture coordinates (u v, s t or texture_u
// texture_v) and colors (red green blue; 8-bit values are divided by 255),
// and the face element's vertex_indices (or vertex_index) list. Other elements
// and properties are read past. Every count is checked against the bytes the
// file has before anything is allocated (loom/formats/mesh_file_counts.hpp).
#include <cstring>
#include <optional>
#include <utility>

#include "indexed_mesh.hpp"
#include "loom/formats/mesh_file_counts.hpp"
#include "text_numbers.hpp"

namespace loom::io {

namespace {

enum class Scalar { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Scalar> scalar_of(std::string_view t) {
  if (t == "char" || t == "int8") return Scalar::i8;
  if (t == "uchar" || t == "uint8") return Scalar::u8;
  if (t == "short" || t == "int16") return Scalar::i16;
  if (t == "ushort" || t == "uint16") return Scalar::u16;
  if (t == "int" || t == "int32") return Scalar::i32;
  if (t == "uint" || t == "uint32") return Scalar::u32;
  if (t == "float" || t == "float32") return Scalar::f32;
  if (t == "double" || t == "float64") return Scalar::f64;
  return std::nullopt;
}

std::size_t size_of(Scalar s) {
  switch (s) {
    case Scalar::i8: case Scalar::u8: return 1;
    case Scalar::i16: case Scalar::u16: return 2;
    case Scalar::i32: case Scalar::u32: case Scalar::f32: return 4;
    case Scalar::f64: return 8;
  }
  return 1;
}

struct Property {
  std::string name;
  Scalar type = Scalar::f32;
  bool list = false;
  Scalar count_type = Scalar::u8;
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

enum class Format { ascii, little, big };

// Reads values of the body, binary or ASCII, with bounds checks.
class Body {
 public:
  Body(const std::string& bytes, std::size_t start, Format format, const std::string& file)
      : bytes_(bytes), pos_(start), format_(format), place_{file} {
    place_.line = 0;
  }

  double read(Scalar s) {
    if (format_ == Format::ascii) {
      std::string_view t = token();
      if (s == Scalar::f32 || s == Scalar::f64) return parse_finite(t, place_);
      const long long v = parse_integer(t, place_);
      return static_cast<double>(v);
    }
    const std::size_t n = size_of(s);
    if (pos_ + n > bytes_.size()) throw Error(place_.file + ": the file ends inside its data (truncated)");
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    const bool swap = (format_ == Format::big) != big_endian_host();
    if (swap)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (s) {
      case Scalar::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case Scalar::u8: return b[0];
      case Scalar::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Scalar::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Scalar::f32: {
        float v;
        std::memcpy(&v, b, 4);
        if (!std::isfinite(v)) throw Error(place_.file + ": a value is NaN or infinite");
        return v;
      }
      case Scalar::f64: {
        double v;
        std::memcpy(&v, b, 8);
        if (!std::isfinite(v)) throw Error(place_.file + ": a value is NaN or infinite");
        return v;
      }
    }
    return 0;
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }

 private:
  static bool big_endian_host() {
    const std::uint16_t one = 1;
    unsigned char c;
    std::memcpy(&c, &one, 1);
    return c == 0;
  }
  std::string_view token() {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    const std::size_t b = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    if (b == pos_) throw Error(place_.file + ": the file ends inside its data (truncated)");
    return std::string_view(bytes_).substr(b, pos_ - b);
  }
  const std::string& bytes_;
  std::size_t pos_;
  Format format_;
  TextPlace place_;
};

struct Header {
  Format format;
  std::vector<Element> elements;
  std::size_t body_start;  // byte offset of the first element
};

Property parse_property(std::string_view rest, const TextPlace& at) {
  Property p;
  std::string_view t = next_token(rest);
  if (t == "list") {
    p.list = true;
    const auto c = scalar_of(next_token(rest));
    const auto v = scalar_of(next_token(rest));
    if (!c || !v || *c == Scalar::f32 || *c == Scalar::f64)
      throw Error(at.where() + ": a list property needs an integer count type and a value type");
    p.count_type = *c;
    p.type = *v;
  } else {
    const auto s = scalar_of(t);
    if (!s) throw Error(at.where() + ": unknown property type \"" + std::string(t.substr(0, 40)) + "\"");
    p.type = *s;
  }
  p.name = std::string(next_token(rest));
  return p;
}

Header parse_header(const std::string& bytes, const std::string& file) {
  TextPlace at{file};
  std::string_view text = bytes, line;
  if (!next_line(text, line) || line.substr(0, 3) != "ply") throw Error(file + ": not a PLY file (no \"ply\" line)");
  at.line = 1;
  std::optional<Format> format;
  std::vector<Element> elements;
  bool ended = false;
  while (!ended && next_line(text, line)) {
    ++at.line;
    std::string_view rest = line;
    const std::string_view key = next_token(rest);
    if (key == "format") {
      const std::string_view f = next_token(rest);
      if (f == "ascii") format = Format::ascii;
      else if (f == "binary_little_endian") format = Format::little;
      else if (f == "binary_big_endian") format = Format::big;
      else throw Error(at.where() + ": unknown PLY format \"" + std::string(f.substr(0, 40)) + "\"");
    } else if (key == "element") {
      Element e;
      e.name = std::string(next_token(rest));
      e.count = parse_integer(next_token(rest), at);
      if (e.count < 0) throw Error(at.where() + ": negative element count");
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) throw Error(at.where() + ": a property before any element");
      elements.back().properties.push_back(parse_property(rest, at));
    } else if (key == "end_header") {
      ended = true;
    } else if (key != "comment" && key != "obj_info" && !key.empty()) {
      throw Error(at.where() + ": unknown header line \"" + std::string(key.substr(0, 40)) + "\"");
    }
  }
  if (!ended) throw Error(file + ": the header has no end_header");
  if (!format) throw Error(file + ": the header has no format line");
  return {*format, std::move(elements), bytes.size() - text.size()};
}

// Where the vertex attributes Loom reads sit among an element's properties (-1: absent).
struct VertexColumns {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, u = -1, v = -1, r = -1, g = -1, b = -1;
  bool normals() const { return nx >= 0 && ny >= 0 && nz >= 0; }
  bool uv() const { return u >= 0 && v >= 0; }
  bool colors() const { return r >= 0 && g >= 0 && b >= 0; }
};

// The property names each column goes by.
constexpr std::pair<const char*, int VertexColumns::*> vertex_names[] = {
    {"x", &VertexColumns::x},   {"y", &VertexColumns::y},    {"z", &VertexColumns::z},
    {"nx", &VertexColumns::nx}, {"ny", &VertexColumns::ny},  {"nz", &VertexColumns::nz},
    {"u", &VertexColumns::u},   {"s", &VertexColumns::u},    {"texture_u", &VertexColumns::u},
    {"v", &VertexColumns::v},   {"t", &VertexColumns::v},    {"texture_v", &VertexColumns::v},
    {"red", &VertexColumns::r}, {"r", &VertexColumns::r},    {"green", &VertexColumns::g},
    {"g", &VertexColumns::g},   {"blue", &VertexColumns::b}, {"b", &VertexColumns::b}};

VertexColumns vertex_columns(const Element& e, const std::string& file) {
  VertexColumns c;
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Property& p = e.properties[k];
    if (p.list) continue;
    for (const auto& [name, column] : vertex_names)
      if (p.name == name) c.*column = static_cast<int>(k);
  }
  if (c.x < 0 || c.y < 0 || c.z < 0) throw Error(file + ": the vertex element has no x, y, z");
  return c;
}

// The face element's vertex index list (the last, if it names several).
int face_list(const Element& e, const std::string& file) {
  int list = -1;
  for (std::size_t k = 0; k < e.properties.size(); ++k)
    if (e.properties[k].list && (e.properties[k].name == "vertex_indices" || e.properties[k].name == "vertex_index"))
      list = static_cast<int>(k);
  if (list < 0) throw Error(file + ": the face element has no vertex_indices list");
  return list;
}

void add_vertex(const Element& e, const VertexColumns& c, const std::vector<double>& values, IndexedMesh& m) {
  const auto at = [&](int i) { return values[static_cast<std::size_t>(i)]; };
  m.V.emplace_back(at(c.x), at(c.y), at(c.z));
  if (c.normals()) m.N.emplace_back(at(c.nx), at(c.ny), at(c.nz));
  if (c.uv()) m.UV.emplace_back(at(c.u), at(c.v));
  if (c.colors()) {
    // 8-bit colors are 0..255.
    const Scalar red = e.properties[static_cast<std::size_t>(c.r)].type;
    const double s = red == Scalar::u8 || red == Scalar::i8 ? 1.0 / 255 : 1.0;
    m.C.emplace_back(at(c.r) * s, at(c.g) * s, at(c.b) * s);
  }
}

// Reads a list property of instance `r`; face indices (when `indices`) become
// a polygon of m, other lists are read past.
void read_list(Body& body, const Element& e, const Property& p, long long r, bool indices, IndexedMesh& m,
               const std::string& file) {
  const double count = body.read(p.count_type);
  if (count < 0) throw Error(file + ": a negative list length in " + e.name + " " + std::to_string(r));
  if (count > static_cast<double>(body.remaining()))
    throw Error(file + ": a list in " + e.name + " " + std::to_string(r) + " is longer than the file");
  if (indices && count < 3)
    throw Error(file + ": face " + std::to_string(r) + " has " + std::to_string(static_cast<int>(count)) +
                " vertices (at least 3 needed)");
  for (int c = 0; c < static_cast<int>(count); ++c) {
    const double idx = body.read(p.type);
    if (!indices) continue;
    if (!(idx >= 0) || idx >= static_cast<double>(m.V.size()) || idx != std::floor(idx))
      throw Error(file + ": face " + std::to_string(r) + " has vertex index " +
                  std::to_string(static_cast<long long>(idx)) + " outside [0, " + std::to_string(m.V.size()) + ")");
    m.corner_v.push_back(static_cast<int>(idx));
  }
  if (indices) m.polygon_start.push_back(static_cast<int>(m.corner_v.size()));
}

}  // namespace

IndexedMesh read_ply_file(const std::string& bytes, const std::string& file) {
  const Header header = parse_header(bytes, file);
  // Counts beyond the file's size are a corrupt header, not an allocation.
  formats::check_declared_counts(bytes, bytes.size(), file);
  Body body(bytes, header.body_start, header.format, file);
  IndexedMesh m;
  bool have_vertices = false, have_faces = false, vertex_normals = false, vertex_uv = false;
  for (const Element& e : header.elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    const VertexColumns columns = is_vertex ? vertex_columns(e, file) : VertexColumns{};
    const int face_indices = is_face ? face_list(e, file) : -1;
    have_vertices |= is_vertex;
    have_faces |= is_face;
    std::vector<double> values(e.properties.size());
    for (long long r = 0; r < e.count; ++r) {
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (p.list)
          read_list(body, e, p, r, static_cast<int>(k) == face_indices, m, file);
        else
          values[k] = body.read(p.type);
      }
      if (is_vertex) add_vertex(e, columns, values, m);
    }
    if (is_vertex) {
      vertex_normals |= columns.normals();
      vertex_uv |= columns.uv();
    }
  }
  if (!have_vertices) throw Error(file + ": no vertex element");
  if (!have_faces) throw Error(file + ": no face element (a point cloud, not a mesh)");
  // Per-vertex attributes: each corner uses its vertex's entry.
  if (vertex_normals) m.corner_n = m.corner_v;
  if (vertex_uv) m.corner_uv = m.corner_v;
  return m;
}

}  // namespace loom::io
