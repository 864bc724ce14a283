#include "loom/point_set.hpp"

#include <cstdint>
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
  for (std::size_t a = 0; a < points.attributes.size(); ++a) {
    const PointAttribute& at = points.attributes[a];
    if (at.name.empty()) throw Error(name + " has an attribute without a name");
    const std::string label = name + "'s attribute \"" + at.name + "\"";
    if (at.values.rows() != points.P.rows())
      throw Error(label + " has " + std::to_string(at.values.rows()) + " rows for " +
                  std::to_string(points.points()) + " points");
    if (at.values.cols() < 1 || at.values.cols() > 3)
      throw Error(label + " has " + std::to_string(at.values.cols()) + " columns (1 to 3 allowed)");
    if (!at.values.allFinite()) throw Error(label + " has NaN or infinite values");
    for (std::size_t b = 0; b < a; ++b)
      if (points.attributes[b].name == at.name) throw Error(label + " is given twice");
  }
}

void TypeTraits<PointSet>::check(const PointSet& v) { require_valid(v, "the point set"); }

std::string TypeTraits<PointSet>::summary(const PointSet& points) {
  std::ostringstream s;
  s << "PointSet " << points.points() << " points";
  if (points.has_radius()) s << ", radius";
  if (points.has_colors()) s << ", colors";
  for (const PointAttribute& a : points.attributes) s << ", " << a.name;
  return s.str();
}

void TypeTraits<PointSet>::write(const PointSet& p, ByteWriter& w) {
  w.matrix(p.P);
  w.matrix(p.radius);
  w.matrix(p.C);
  w.pod(static_cast<std::uint64_t>(p.attributes.size()));
  for (const PointAttribute& a : p.attributes) {
    w.str(a.name);
    w.matrix(a.values);
  }
}

PointSet TypeTraits<PointSet>::read(ByteReader& r) {
  PointSet p;
  p.P = r.matrix<Eigen::MatrixX3d>();
  p.radius = r.matrix<Eigen::VectorXd>();
  p.C = r.matrix<Eigen::MatrixX3d>();
  const auto count = r.pod<std::uint64_t>();
  if (count > 1024) throw Error("stored PointSet has an impossible attribute count");
  for (std::uint64_t a = 0; a < count; ++a) {
    PointAttribute at;
    at.name = r.str();
    at.values = r.matrix<Eigen::MatrixXd>();
    p.attributes.push_back(std::move(at));
  }
  return p;
}

std::size_t TypeTraits<PointSet>::bytes(const PointSet& p) {
  std::size_t n = sizeof(double) * static_cast<std::size_t>(p.P.size() + p.radius.size() + p.C.size());
  for (const PointAttribute& a : p.attributes) n += a.name.size() + sizeof(double) * static_cast<std::size_t>(a.values.size());
  return n;
}

}  // namespace loom
