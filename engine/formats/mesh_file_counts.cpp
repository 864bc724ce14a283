#include "loom/formats/mesh_file_counts.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <vector>

#include "loom/error.hpp"

namespace loom::formats {

namespace {

std::string_view next_line(std::string_view& text) {
  const std::size_t end = text.find('\n');
  std::string_view line = text.substr(0, end);
  text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

std::string_view next_token(std::string_view& text) {
  const std::size_t b = text.find_first_not_of(" \t\r\n\f\v");
  if (b == std::string_view::npos) return text = {};
  const std::size_t e = text.find_first_of(" \t\r\n\f\v", b);
  const std::string_view t = text.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b);
  text = e == std::string_view::npos ? std::string_view() : text.substr(e);
  return t;
}

// A non-negative count, or -1 when the token is not one (the reader reports that).
long long count_of(std::string_view t) {
  long long v = -1;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size() && v >= 0 ? v : -1;
}

[[noreturn]] void too_many(const std::string& file, long long count, std::string_view what, std::uintmax_t bytes) {
  throw Error(file + ": the header declares " + std::to_string(count) + " " + std::string(what) + " but the file has " +
              std::to_string(bytes) + " bytes, too few for them (corrupt or truncated)");
}

// Bytes a PLY scalar takes in binary (0: not a type name).
std::uintmax_t ply_scalar_bytes(std::string_view t) {
  if (t == "char" || t == "int8" || t == "uchar" || t == "uint8") return 1;
  if (t == "short" || t == "int16" || t == "ushort" || t == "uint16") return 2;
  if (t == "int" || t == "int32" || t == "uint" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// PLY: every element instance takes at least its properties' bytes (a list
// its count's), or two bytes per property in ASCII; all elements together fit
// the bytes after the header.
void check_ply(std::string_view head, std::uintmax_t file_size, const std::string& file) {
  struct Element {
    std::string name;
    long long count;
    std::uintmax_t binary_bytes = 0, properties = 0;
  };
  std::vector<Element> elements;
  bool ascii = false;
  std::string_view text = head;
  next_line(text);  // "ply"
  while (!text.empty()) {
    std::string_view rest = next_line(text);
    const std::string_view key = next_token(rest);
    if (key == "end_header") {
      // (+1 in ASCII: the last value needs no separator after it.)
      const std::uintmax_t body =
          file_size - std::min<std::uintmax_t>(file_size, head.size() - text.size()) + (ascii ? 1 : 0);
      std::uintmax_t needed = 0;
      for (const Element& e : elements) {
        const std::uintmax_t per = ascii ? 2 * e.properties : e.binary_bytes;
        if (per > 0 && (std::uintmax_t(e.count) > body / per || needed + std::uintmax_t(e.count) * per > body))
          too_many(file, e.count, e.name + " elements", file_size);
        needed += std::uintmax_t(e.count) * per;
      }
      return;
    }
    if (key == "format") {
      ascii = next_token(rest) == "ascii";
    } else if (key == "element") {
      const std::string name(next_token(rest));
      elements.push_back({name, std::max(0LL, count_of(next_token(rest)))});
    } else if (key == "property" && !elements.empty()) {
      std::string_view type = next_token(rest);
      if (type == "list") type = next_token(rest);  // its count's type: one per instance at least
      elements.back().binary_bytes += ply_scalar_bytes(type);
      ++elements.back().properties;
    }
  }
}

// The tokens of an OFF file's content lines (comments cut), `n` at most.
std::vector<std::string_view> off_tokens(std::string_view head, std::size_t n) {
  std::vector<std::string_view> tokens;
  std::string_view text = head;
  while (!text.empty() && tokens.size() < n) {
    std::string_view line = next_line(text);
    line = line.substr(0, line.find('#'));
    for (std::string_view t = next_token(line); !t.empty() && tokens.size() < n; t = next_token(line))
      tokens.push_back(t);
  }
  return tokens;
}

// OFF: "[C|N|...]OFF" then #vertices #faces #edges (on the keyword's line or
// the next content line); a vertex is at least 3 numbers, a face at least 4.
void check_off(std::string_view head, std::uintmax_t file_size, const std::string& file) {
  const std::vector<std::string_view> t = off_tokens(head, 3);
  if (t.size() < 3) return;
  const long long vertices = count_of(t[1]), faces = count_of(t[2]);
  if (vertices > 0 && std::uintmax_t(vertices) > file_size / 6) too_many(file, vertices, "vertices", file_size);
  if (faces > 0 && std::uintmax_t(faces) > file_size / 8) too_many(file, faces, "faces", file_size);
}

// DirectX .x (text): each Mesh, MeshNormals, MeshTextureCoords and
// MeshVertexColors block starts with its item count; an item takes at least
// 2 bytes per value ("0;"), a vertex or normal 3 values, a texture coordinate 2.
void check_x(std::string_view head, std::uintmax_t file_size, const std::string& file) {
  static constexpr std::pair<std::string_view, std::uintmax_t> blocks[] = {
      {"Mesh", 6}, {"MeshNormals", 6}, {"MeshTextureCoords", 4}, {"MeshVertexColors", 4}};
  std::string_view text = head.substr(16);  // past "xof 0303txt 0032"
  while (!text.empty()) {
    std::string_view t = next_token(text);
    if (const std::size_t brace = t.find('{'); brace != std::string_view::npos) t = t.substr(0, brace);
    for (const auto& [name, bytes_per_item] : blocks) {
      if (t != name) continue;
      // The block: an optional name, "{", then the count and ';'.
      const std::size_t brace = text.find('{');
      if (brace == std::string_view::npos || brace > 512) break;
      std::string_view body = text.substr(brace + 1);
      const std::size_t b = body.find_first_not_of(" \t\r\n\f\v");
      if (b == std::string_view::npos) break;
      body = body.substr(b);
      const std::size_t e = body.find_first_not_of("0123456789");
      const long long n = count_of(body.substr(0, e));
      if (n > 0 && std::uintmax_t(n) > file_size / bytes_per_item)
        too_many(file, n, name == "Mesh" ? "vertices in a Mesh" : "items in a " + std::string(name), file_size);
    }
  }
}

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

bool is_off(std::string_view head) {
  const std::vector<std::string_view> t = off_tokens(head, 1);
  return !t.empty() && t[0].size() >= 3 && t[0].size() <= 6 && t[0].substr(t[0].size() - 3) == "OFF";
}

bool is_text_x(std::string_view head) {
  return head.size() >= 16 && starts_with(head, "xof ") && head.substr(8, 4) == "txt ";
}

}  // namespace

void check_declared_counts(std::string_view head, std::uintmax_t file_size, const std::string& file) {
  if (starts_with(head, "ply\n") || starts_with(head, "ply\r\n"))
    check_ply(head, file_size, file);
  else if (is_text_x(head))
    check_x(head, file_size, file);
  else if (is_off(head))
    check_off(head, file_size, file);
}

void check_declared_counts(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || !std::filesystem::is_regular_file(path, ec)) return;
  std::ifstream in(path, std::ios::binary);
  std::string head(static_cast<std::size_t>(std::min<std::uintmax_t>(size, 1 << 16)), '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(head.size()))) return;
  if (is_text_x(head) && size > head.size()) {
    // A text .x file's meshes may start anywhere: read it all (the importer will).
    head.resize(static_cast<std::size_t>(size));
    if (!in.read(head.data() + (1 << 16), static_cast<std::streamsize>(size - (1 << 16)))) return;
  }
  check_declared_counts(head, size, path.string());
}

}  // namespace loom::formats
