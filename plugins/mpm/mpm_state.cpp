#include "mpm_state.hpp"
#include <algorithm>
#include <cmath>

#include <Eigen/LU>

namespace loom::mpm {
namespace {

// Fixed-size Eigen vectors are not trivially copyable by the type system, but
// are plain arrays of doubles in memory: written as raw bytes with a count.
template <class T>
void write_array(ByteWriter& w, const std::vector<T>& v) {
  w.pod<std::uint64_t>(v.size());
  w.bytes(v.data(), sizeof(T) * v.size());
}
template <class T>
void read_array(ByteReader& r, std::vector<T>& v) {
  const auto n = r.pod<std::uint64_t>();
  if (n > r.remaining() / sizeof(T)) throw Error("stored MPMState is truncated");
  v.resize(static_cast<std::size_t>(n));
  r.bytes(v.data(), sizeof(T) * v.size());
}

template <int D>
void write_particles(ByteWriter& w, const Particles<D>& p) {
  Particles<D>::each_array([&](auto array) { write_array(w, p.*array); });
}
template <int D>
void read_particles(ByteReader& r, Particles<D>& p) {
  Particles<D>::each_array([&](auto array) { read_array(r, p.*array); });
  bool same_lengths = true;
  Particles<D>::each_array([&](auto array) { same_lengths = same_lengths && (p.*array).size() == p.x.size(); });
  if (!same_lengths) throw Error("stored MPMState has attribute arrays of different lengths");
  for (Material m : p.material)
    if (static_cast<int>(m) > static_cast<int>(Material::sand))
      throw Error("stored MPMState has an unknown material");
}

template <int D>
PointSet point_set(const Particles<D>& p, double radius) {
  PointSet out;
  const int n = p.size();
  out.P.setZero(n, 3);
  out.C.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    out.P.row(i).template head<D>() = p.x[i].transpose();
    out.C.row(i) = p.color[i].template cast<double>().transpose();
  }
  out.radius.setConstant(n, radius);
  return out;
}

template <int D>
PointSet particle_points(const Particles<D>& p, double radius) {
  PointSet out = point_set(p, radius);
  const int n = p.size();
  Eigen::MatrixXd velocity = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd mass(n), volume(n), J(n), plastic_J(n), strain(n), material(n);
  for (int i = 0; i < n; ++i) {
    velocity.row(i).template head<D>() = p.v[i].transpose();
    mass[i] = p.mass[i];
    volume[i] = p.volume[i];
    const bool fluid = p.material[i] == Material::fluid, snow = p.material[i] == Material::snow;
    plastic_J[i] = snow ? p.J[i] : 1.0;
    J[i] = fluid ? p.J[i] : p.F[i].determinant() * plastic_J[i];
    strain[i] = p.material[i] == Material::sand ? p.q[i] : 0.0;
    material[i] = static_cast<double>(p.material[i]);
  }
  out.attributes = {{"velocity", velocity},  {"mass", mass},     {"volume", volume},
                    {"J", J},                {"snow_plastic_J", plastic_J},
                    {"plastic_strain", strain}, {"material", material}};
  return out;
}

}  // namespace

PointSet point_set(const MpmState& state, double radius) {
  return state.dim == 2 ? point_set(state.p2, radius) : point_set(state.p3, radius);
}

PointSet particle_points(const MpmState& state, double radius) {
  return state.dim == 2 ? particle_points(state.p2, radius) : particle_points(state.p3, radius);
}

}  // namespace loom::mpm

namespace mpm = loom::mpm;

std::string loom::TypeTraits<mpm::MpmState>::summary(const mpm::MpmState& s) {
  return std::to_string(s.size()) + " particles (" + std::to_string(s.dim) + "D) at t = " +
         std::to_string(s.time) + " s";
}

namespace {
template <int D>
bool finite(const mpm::Particles<D>& p) {
  const auto all = [](const auto& list) {
    return std::all_of(list.begin(), list.end(), [](const auto& m) { return m.allFinite(); });
  };
  return all(p.x) && all(p.v) && all(p.C) && all(p.F) &&
         std::all_of(p.J.begin(), p.J.end(), [](double j) { return std::isfinite(j); });
}
}  // namespace

void loom::TypeTraits<mpm::MpmState>::check(const mpm::MpmState& s) {
  if (!(s.dim == 2 ? finite(s.p2) : finite(s.p3)))
    throw loom::Error("particles have NaN or infinite positions, velocities or deformations: the simulation "
                      "diverged (lower cfl or dt_max, or the material's stiffness)");
}

void loom::TypeTraits<mpm::MpmState>::write(const mpm::MpmState& s, loom::ByteWriter& w) {
  w.pod<std::int32_t>(s.dim);
  w.pod(s.time);
  w.pod<std::int32_t>(s.substeps);
  if (s.dim == 2)
    mpm::write_particles(w, s.p2);
  else
    mpm::write_particles(w, s.p3);
}

mpm::MpmState loom::TypeTraits<mpm::MpmState>::read(loom::ByteReader& r) {
  mpm::MpmState s;
  s.dim = r.pod<std::int32_t>();
  if (s.dim != 2 && s.dim != 3) throw Error("stored MPMState has dimension " + std::to_string(s.dim));
  s.time = r.pod<double>();
  s.substeps = r.pod<std::int32_t>();
  if (s.dim == 2)
    mpm::read_particles(r, s.p2);
  else
    mpm::read_particles(r, s.p3);
  return s;
}
