#include "loom/polylines.hpp"

#include <sstream>

namespace loom {

void require_valid(const Polylines& lines, const char* what) {
  const std::string name = what;
  if (!lines.P.allFinite()) throw Error(name + " has NaN or infinite positions");
  if (lines.E.size() > 0 && (lines.E.minCoeff() < 0 || lines.E.maxCoeff() >= lines.vertices()))
    throw Error(name + " has segment indices outside [0, " + std::to_string(lines.vertices()) + ")");
  if (lines.C.rows() != 0 && lines.C.rows() != lines.P.rows())
    throw Error(name + " has " + std::to_string(lines.C.rows()) + " colors for " +
                std::to_string(lines.vertices()) + " vertices");
}

void TypeTraits<Polylines>::check(const Polylines& v) { require_valid(v, "the polylines"); }

std::string TypeTraits<Polylines>::summary(const Polylines& lines) {
  std::ostringstream s;
  s << "Polylines " << lines.vertices() << " vertices, " << lines.segments() << " segments";
  if (lines.has_colors()) s << ", colors";
  return s.str();
}

void TypeTraits<Polylines>::write(const Polylines& l, ByteWriter& w) {
  w.matrix(l.P);
  w.matrix(l.E);
  w.matrix(l.C);
}

Polylines TypeTraits<Polylines>::read(ByteReader& r) {
  Polylines l;
  l.P = r.matrix<Eigen::MatrixX3d>();
  l.E = r.matrix<Eigen::MatrixX2i>();
  l.C = r.matrix<Eigen::MatrixX3d>();
  return l;
}

std::size_t TypeTraits<Polylines>::bytes(const Polylines& l) {
  return sizeof(double) * static_cast<std::size_t>(l.P.size() + l.C.size()) +
         sizeof(int) * static_cast<std::size_t>(l.E.size());
}

}  // namespace loom
