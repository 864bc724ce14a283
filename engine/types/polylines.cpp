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

std::string TypeTraits<Polylines>::summary(const Polylines& lines) {
  std::ostringstream s;
  s << "Polylines " << lines.vertices() << " vertices, " << lines.segments() << " segments";
  if (lines.has_colors()) s << ", colors";
  return s.str();
}

}  // namespace loom
