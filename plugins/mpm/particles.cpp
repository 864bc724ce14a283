#include "particles.hpp"

namespace loom::mpm {

Lame lame_parameters(Material material, double E, double nu) {
  if (material == Material::fluid) return {0.0, E};
  return {E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))};
}

template <int D>
void Particles<D>::reserve(std::size_t n) {
  x.reserve(n), v.reserve(n), C.reserve(n), F.reserve(n), J.reserve(n), q.reserve(n);
  material.reserve(n), mu.reserve(n), lambda.reserve(n), mass.reserve(n), volume.reserve(n);
  color.reserve(n);
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
  auto cat = [](auto& a, const auto& b) { a.insert(a.end(), b.begin(), b.end()); };
  cat(x, o.x), cat(v, o.v), cat(C, o.C), cat(F, o.F), cat(J, o.J), cat(q, o.q), cat(material, o.material);
  cat(mu, o.mu), cat(lambda, o.lambda), cat(mass, o.mass), cat(volume, o.volume);
  cat(color, o.color);
}

template struct Particles<2>;
template struct Particles<3>;

}  // namespace loom::mpm
