#include "loom/point_set.hpp"

#include <sstream>

namespace loom {

void require_valid(const PointSet& points, const char* what) {
  const std::string name = what;
  if (!points.P.allFinite()) throw Error(name + " has NaN or infinite positions");
  if (points.radius.size() != 0 && points.radius.size() != points.P.rows())
    throw Error(name + " has " + std::to_string(points.radius.size()) + " radii for " +
                std::to_string(points.points()) + " points");
  if (points.radius.size() != 0 && !(points.radius.array() >= 0).all())
    throw Error(name + " has negative or NaN radii");
  if (points.C.rows() != 0 && points.C.rows() != points.P.rows())
    throw Error(name + " has " + std::to_string(points.C.rows()) + " colors for " +
                std::to_string(points.points()) + " points");
}

void TypeTraits<PointSet>::check(const PointSet& v) { require_valid(v, "the point set"); }

std::string TypeTraits<PointSet>::summary(const PointSet& points) {
  std::ostringstream s;
  s << "PointSet " << points.points() << " points";
  if (points.has_radius()) s << ", radius";
  if (points.has_colors()) s << ", colors";
  return s.str();
}

void TypeTraits<PointSet>::write(const PointSet& p, ByteWriter& w) {
  w.matrix(p.P);
  w.matrix(p.radius);
  w.matrix(p.C);
}

PointSet TypeTraits<PointSet>::read(ByteReader& r) {
  PointSet p;
  p.P = r.matrix<Eigen::MatrixX3d>();
  p.radius = r.matrix<Eigen::VectorXd>();
  p.C = r.matrix<Eigen::MatrixX3d>();
  return p;
}

std::size_t TypeTraits<PointSet>::bytes(const PointSet& p) {
  return sizeof(double) * static_cast<std::size_t>(p.P.size() + p.radius.size() + p.C.size());
}

}  // namespace loom
