#include "cloth_state.hpp"

#include <memory>

namespace loom::cloth {

Mesh state_mesh(const ClothState& state) {
  Mesh mesh;
  mesh.V = state.x;
  mesh.F = state.system->F;
  mesh.UV = state.system->UV;
  mesh.C = state.system->C;
  return mesh;
}

PointSet state_points(const ClothState& state) {
  PointSet points;
  points.P = state.x;
  points.C = state.system->C;
  points.attributes = {{"velocity", state.v},
                       {"mass", state.system->mass},
                       {"fixed", state.system->fixed.cast<double>()}};
  return points;
}

}  // namespace loom::cloth

namespace loom {

std::string TypeTraits<cloth::ClothState>::summary(const cloth::ClothState& s) {
  return "ClothState " + std::to_string(s.system->vertices()) + " vertices, " +
         std::to_string(s.system->spring_count()) + " springs, " +
         std::to_string(s.system->fixed_count()) + " fixed, t = " + std::to_string(s.time) + " s";
}

void TypeTraits<cloth::ClothState>::check(const cloth::ClothState& s) {
  if (!s.x.allFinite() || !s.v.allFinite())
    throw Error("positions or velocities are NaN or infinite: the step diverged (use more substeps, "
                "an implicit solver, or smaller forces)");
}

void TypeTraits<cloth::ClothState>::write(const cloth::ClothState& s, ByteWriter& w) {
  const cloth::SpringSystem& sys = *s.system;
  w.matrix(sys.X);
  w.matrix(sys.springs);
  w.matrix(sys.rest_length);
  w.matrix(sys.stiffness);
  w.matrix(sys.mass);
  w.matrix(sys.fixed);
  w.matrix(sys.F);
  w.matrix(sys.UV);
  w.matrix(sys.C);
  w.matrix(s.x);
  w.matrix(s.v);
  w.pod(s.time);
}

cloth::ClothState TypeTraits<cloth::ClothState>::read(ByteReader& r) {
  auto sys = std::make_shared<cloth::SpringSystem>();
  sys->X = r.matrix<Eigen::MatrixX3d>();
  sys->springs = r.matrix<Eigen::MatrixX2i>();
  sys->rest_length = r.matrix<Eigen::VectorXd>();
  sys->stiffness = r.matrix<Eigen::VectorXd>();
  sys->mass = r.matrix<Eigen::VectorXd>();
  sys->fixed = r.matrix<Eigen::VectorXi>();
  sys->F = r.matrix<Eigen::MatrixX3i>();
  sys->UV = r.matrix<Eigen::MatrixX2d>();
  sys->C = r.matrix<Eigen::MatrixX3d>();
  cloth::require_valid(*sys);
  cloth::ClothState s;
  s.x = r.matrix<Eigen::MatrixX3d>();
  s.v = r.matrix<Eigen::MatrixX3d>();
  s.time = r.pod<double>();
  if (s.x.rows() != sys->X.rows() || s.v.rows() != sys->X.rows())
    throw Error("stored ClothState has positions or velocities that do not match its system");
  s.system = std::move(sys);
  return s;
}

}  // namespace loom
