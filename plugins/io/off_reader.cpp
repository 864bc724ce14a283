// Object File Format: "OFF" (or "COFF" with per-vertex colors), the counts
// #V #F #E, then vertices and polygons "n i0 ... i(n-1)" with 0-based indices.
#include "indexed_mesh.hpp"
#include "loom/formats/mesh_file_counts.hpp"
#include "text_numbers.hpp"

namespace loom::io {

IndexedMesh read_off_file(const std::string& bytes, const std::string& file) {
  IndexedMesh m;
  TextPlace at{file};
  std::string_view text = bytes, line;
  // The next non-empty, non-comment line's tokens.
  auto content = [&](std::string_view& rest) {
    while (next_line(text, line)) {
      ++at.line;
      std::string_view l = line.substr(0, line.find('#'));
      if (l.find_first_not_of(" \t\r\f\v") == std::string_view::npos) continue;
      rest = l;
      return true;
    }
    return false;
  };
  std::string_view rest;
  if (!content(rest)) throw Error(file + ": empty file");
  std::string_view magic = next_token(rest);
  const bool colors = magic == "COFF";
  if (magic != "OFF" && !colors) throw Error(file + ": not an OFF file (it starts with \"" + std::string(magic.substr(0, 20)) + "\")");
  // The counts may follow the keyword on its line or stand on the next.
  std::string_view counts = rest;
  if (counts.find_first_not_of(" \t\r\f\v") == std::string_view::npos && !content(counts))
    throw Error(file + ": missing the vertex and face counts");
  std::string_view t1 = next_token(counts);
  if (t1.empty()) throw Error(at.where() + ": missing the vertex and face counts");
  const long long nv = parse_integer(t1, at);
  const std::string_view t2 = next_token(counts);
  if (t2.empty()) throw Error(at.where() + ": missing the face count");
  const long long nf = parse_integer(t2, at);
  if (nv < 0 || nf < 0)
    throw Error(at.where() + ": negative vertex/face counts " + std::to_string(nv) + "/" + std::to_string(nf));
  // Counts beyond the file's size are a corrupt header, not an allocation.
  formats::check_declared_counts(bytes, bytes.size(), file);
  m.V.reserve(static_cast<std::size_t>(nv));
  for (long long v = 0; v < nv; ++v) {
    if (!content(rest)) throw Error(file + ": the file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices");
    double x[3];
    for (double& c : x) {
      std::string_view t = next_token(rest);
      if (t.empty()) throw Error(at.where() + ": a vertex needs x y z");
      c = parse_finite(t, at);
    }
    m.V.emplace_back(x[0], x[1], x[2]);
    if (colors) {
      double c[3];
      for (double& k : c) {
        std::string_view t = next_token(rest);
        if (t.empty()) throw Error(at.where() + ": a COFF vertex needs x y z r g b");
        k = parse_finite(t, at);
      }
      const double scale = (c[0] > 1 || c[1] > 1 || c[2] > 1) ? 1.0 / 255 : 1.0;
      m.C.emplace_back(c[0] * scale, c[1] * scale, c[2] * scale);
    }
  }
  for (long long f = 0; f < nf; ++f) {
    if (!content(rest)) throw Error(file + ": the file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    const long long n = parse_integer(next_token(rest), at);
    if (n < 3 || n > 1024) throw Error(at.where() + ": a face needs 3 to 1024 vertices, got " + std::to_string(n));
    for (long long k = 0; k < n; ++k) {
      std::string_view t = next_token(rest);
      if (t.empty()) throw Error(at.where() + ": the face lists fewer than " + std::to_string(n) + " vertices");
      const long long i = parse_integer(t, at);
      if (i < 0 || i >= nv) throw Error(at.where() + ": vertex index " + std::to_string(i) + " out of range [0, " + std::to_string(nv) + ")");
      m.corner_v.push_back(static_cast<int>(i));
    }
    m.polygon_start.push_back(static_cast<int>(m.corner_v.size()));
  }
  return m;
}

}  // namespace loom::io
