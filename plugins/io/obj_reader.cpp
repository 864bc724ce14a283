// Wavefront OBJ: v, vt, vn and f records with 1-based or negative (relative)
// indices. Lines (l) and points (p) are counted as dropped; materials, groups
// and smoothing groups are ignored.
#include "indexed_mesh.hpp"
#include "text_numbers.hpp"

namespace loom::io {

namespace {

// A 1-based or negative OBJ index into a pool of `size` entries, as 0-based.
int resolve(std::string_view token, std::size_t size, const char* what, const TextPlace& at) {
  const long long i = parse_integer(token, at);
  const long long n = static_cast<long long>(size);
  const long long r = i > 0 ? i - 1 : n + i;
  if (i == 0 || r < 0 || r >= n)
    throw Error(at.where() + ": " + what + " index " + std::string(token) + " out of range (" +
                std::to_string(size) + " defined so far)");
  return static_cast<int>(r);
}

}  // namespace

IndexedMesh read_obj_file(const std::string& bytes, const std::string& file) {
  IndexedMesh m;
  TextPlace at{file};
  std::string_view text = bytes, line;
  bool colors = true;
  while (next_line(text, line)) {
    ++at.line;
    std::string_view rest = line;
    const std::string_view tag = next_token(rest);
    if (tag.empty() || tag[0] == '#') continue;
    if (tag == "v") {
      double x[6];
      int k = 0;
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        if (k == 6) throw Error(at.where() + ": a vertex has more than 6 numbers");
        x[k++] = parse_finite(t, at);
      }
      if (k != 3 && k != 4 && k != 6) throw Error(at.where() + ": a vertex needs x y z (or x y z r g b)");
      m.V.emplace_back(x[0], x[1], x[2]);
      if (k == 6) m.C.emplace_back(x[3], x[4], x[5]);
      colors = colors && k == 6;
    } else if (tag == "vt") {
      double x[3] = {0, 0, 0};
      int k = 0;
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        if (k == 3) throw Error(at.where() + ": a texture coordinate has more than 3 numbers");
        x[k++] = parse_finite(t, at);
      }
      if (k < 1) throw Error(at.where() + ": a texture coordinate needs u [v]");
      m.UV.emplace_back(x[0], x[1]);
    } else if (tag == "vn") {
      double x[3];
      int k = 0;
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        if (k == 3) throw Error(at.where() + ": a normal has more than 3 numbers");
        x[k++] = parse_finite(t, at);
      }
      if (k != 3) throw Error(at.where() + ": a normal needs x y z");
      m.N.emplace_back(x[0], x[1], x[2]);
    } else if (tag == "f") {
      int corners = 0;
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        // v, v/vt, v//vn or v/vt/vn
        const std::size_t s1 = t.find('/');
        const std::string_view tv = t.substr(0, s1);
        std::string_view tt, tn;
        if (s1 != std::string_view::npos) {
          const std::size_t s2 = t.find('/', s1 + 1);
          tt = t.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
          if (s2 != std::string_view::npos) tn = t.substr(s2 + 1);
        }
        m.corner_v.push_back(resolve(tv, m.V.size(), "vertex", at));
        m.corner_uv.push_back(tt.empty() ? -1 : resolve(tt, m.UV.size(), "texture coordinate", at));
        m.corner_n.push_back(tn.empty() ? -1 : resolve(tn, m.N.size(), "normal", at));
        ++corners;
      }
      if (corners < 3) throw Error(at.where() + ": a face needs at least 3 vertices, got " + std::to_string(corners));
      m.polygon_start.push_back(static_cast<int>(m.corner_v.size()));
    } else if (tag == "l" || tag == "p") {
      ++m.dropped;
    }
    // o, g, s, usemtl, mtllib and unknown records carry no geometry.
  }
  if (!colors || m.C.size() != m.V.size()) m.C.clear();
  bool any_uv = false, any_n = false;
  for (int i : m.corner_uv) any_uv = any_uv || i >= 0;
  for (int i : m.corner_n) any_n = any_n || i >= 0;
  if (!any_uv) m.corner_uv.clear();
  if (!any_n) m.corner_n.clear();
  return m;
}

}  // namespace loom::io
