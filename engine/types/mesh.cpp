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

std::string TypeTraits<Mesh>::summary(const Mesh& mesh) {
  std::ostringstream s;
  s << "Mesh " << mesh.vertices() << " vertices, " << mesh.faces() << " faces";
  if (mesh.has_uv()) s << ", UV";
  if (mesh.has_normals()) s << ", normals";
  if (mesh.has_colors()) s << ", colors";
  return s.str();
}

}  // namespace loom
