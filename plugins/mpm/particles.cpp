#include "particles.hpp"

namespace loom::mpm {

Lame lame_parameters(Material material, double E, double nu) {
  if (material == Material::fluid) return {0.0, E};
  return {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))};
}

template <int D>
void Particles<D>::reserve(std::size_t n) {
  each_array([&](auto array) { (this->*array).reserve(n); });
}

template <int D>
void Particles<D>::add(const Vec& position, const Vec& velocity, Material m, const Lame& lame,
                       double particle_mass, double particle_volume, const Eigen::Vector3f& rgb) {
  x.push_back(position);
  v.push_back(velocity);
  C.push_back(Mat::Zero());
  F.push_back(Mat::Identity());
  J.push_back(1.0);
  q.push_back(0.0);
  material.push_back(m);
  mu.push_back(lame.mu);
  lambda.push_back(lame.lambda);
  mass.push_back(particle_mass);
  volume.push_back(particle_volume);
  color.push_back(rgb);
}

template <int D>
void Particles<D>::append(const Particles& o) {
  each_array([&](auto array) { (this->*array).insert((this->*array).end(), (o.*array).begin(), (o.*array).end()); });
}

template struct Particles<2>;
template struct Particles<3>;

}  // namespace loom::mpm
