#include "bspline_splat.hpp"

#include <cmath>

#include "loom/error.hpp"

namespace loom::volume {

AxisWeights quadratic_bspline(double x) {
  const double base = std::floor(x - 0.5), f = x - base;
  return {static_cast<int>(base), {0.5 * (1.5 - f) * (1.5 - f), 0.75 - (f - 1) * (f - 1), 0.5 * (f - 0.5) * (f - 0.5)}};
}

Volume splat_points(const Eigen::MatrixX3d& positions, const Eigen::VectorXd& mass, const Eigen::MatrixX3d& velocity,
                    double voxel_size) {
  // OpenVDB's coordinates are 32-bit: keep every stencil well inside them.
  if (positions.rows() > 0 && positions.cwiseAbs().maxCoeff() / voxel_size > 1e9)
    throw Error("points lie more than 1e9 voxels from the origin: raise voxel_size");
  // Accumulate in double (mass and momentum), then store floats: the grid
  // total then matches Σ m_p to float rounding of each voxel only.
  openvdb::DoubleGrid::Ptr grid_mass = openvdb::DoubleGrid::create(0.0);
  openvdb::Vec3DGrid::Ptr momentum = openvdb::Vec3DGrid::create(openvdb::Vec3d(0.0));
  auto mass_at = grid_mass->getAccessor();
  auto momentum_at = momentum->getAccessor();
  const bool moving = velocity.rows() == positions.rows() && positions.rows() > 0;
  for (Eigen::Index p = 0; p < positions.rows(); ++p) {
    const AxisWeights wx = quadratic_bspline(positions(p, 0) / voxel_size);
    const AxisWeights wy = quadratic_bspline(positions(p, 1) / voxel_size);
    const AxisWeights wz = quadratic_bspline(positions(p, 2) / voxel_size);
    const openvdb::Vec3d v =
        moving ? openvdb::Vec3d(velocity(p, 0), velocity(p, 1), velocity(p, 2)) : openvdb::Vec3d(0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          const openvdb::Coord c(wx.base + i, wy.base + j, wz.base + k);
          const double m = wx.w[i] * wy.w[j] * wz.w[k] * mass[p];
          mass_at.setValue(c, mass_at.getValue(c) + m);
          if (moving) momentum_at.setValue(c, momentum_at.getValue(c) + m * v);
        }
  }
  Volume out;
  out.voxel_size = voxel_size;
  const auto transform = openvdb::math::Transform::createLinearTransform(voxel_size);
  openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.0f);
  openvdb::Vec3SGrid::Ptr grid_velocity = moving ? openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f)) : nullptr;
  const double cell = voxel_size * voxel_size * voxel_size;
  auto density_at = density->getAccessor();
  for (auto it = grid_mass->cbeginValueOn(); it; ++it) {
    const double m = *it;
    if (m <= 0) continue;  // only massless points reached it: no matter there
    density_at.setValue(it.getCoord(), static_cast<float>(m / cell));
    if (moving) grid_velocity->tree().setValue(it.getCoord(), openvdb::Vec3s(momentum_at.getValue(it.getCoord()) / m));
  }
  density->setName("density");
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->setTransform(transform);
  out.density = density;
  if (moving) {
    grid_velocity->setName("velocity");
    grid_velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
    grid_velocity->setTransform(transform->copy());
    out.velocity = grid_velocity;
  }
  return out;
}

}  // namespace loom::volume
