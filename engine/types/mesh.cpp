#include "loom/mesh.hpp"

#include <sstream>

namespace loom {

void require_valid(const Mesh& mesh, const char* what) {
  const std::string name = what;
  if (!mesh.V.allFinite()) throw Error(name + " has NaN or infinite vertex positions");
  if (mesh.F.size() > 0 && (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.vertices()))
    throw Error(name + " has face indices outside [0, " + std::to_string(mesh.vertices()) + ")");
  auto rows_ok = [&](Eigen::Index rows) { return rows == 0 || rows == mesh.V.rows(); };
  if (!rows_ok(mesh.UV.rows()) || !rows_ok(mesh.N.rows()) || !rows_ok(mesh.C.rows()))
    throw Error(name + " has attribute rows that do not match its " +
                std::to_string(mesh.vertices()) + " vertices");
}

void TypeTraits<Mesh>::check(const Mesh& v) { require_valid(v, "the mesh"); }

std::string TypeTraits<Mesh>::summary(const Mesh& mesh) {
  std::ostringstream s;
  s << "Mesh " << mesh.vertices() << " vertices, " << mesh.faces() << " faces";
  if (mesh.has_uv()) s << ", UV";
  if (mesh.has_normals()) s << ", normals";
  if (mesh.has_colors()) s << ", colors";
  return s.str();
}

void TypeTraits<Mesh>::write(const Mesh& m, ByteWriter& w) {
  w.matrix(m.V);
  w.matrix(m.F);
  w.matrix(m.UV);
  w.matrix(m.N);
  w.matrix(m.C);
}

Mesh TypeTraits<Mesh>::read(ByteReader& r) {
  Mesh m;
  m.V = r.matrix<Eigen::MatrixX3d>();
  m.F = r.matrix<Eigen::MatrixX3i>();
  m.UV = r.matrix<Eigen::MatrixX2d>();
  m.N = r.matrix<Eigen::MatrixX3d>();
  m.C = r.matrix<Eigen::MatrixX3d>();
  return m;
}

std::size_t TypeTraits<Mesh>::bytes(const Mesh& m) {
  return sizeof(double) * static_cast<std::size_t>(m.V.size() + m.UV.size() + m.N.size() + m.C.size()) +
         sizeof(int) * static_cast<std::size_t>(m.F.size());
}

}  // namespace loom
