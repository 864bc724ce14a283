#include "orbits.hpp"

#include <cmath>

#include "loom/error.hpp"

namespace loom::mpm {
namespace {

bool moves(const NBodySystem& s, int i) {
  return !(s.fixed_central && i == 0) && !s.landed[static_cast<std::size_t>(i)];
}

void accelerations(const NBodySystem& s, std::vector<Eigen::Vector3d>& a) {
  const int n = s.size();
  a.assign(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  const double eps2 = s.softening * s.softening;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (s.landed[static_cast<std::size_t>(i)] || s.landed[static_cast<std::size_t>(j)]) continue;
      const Eigen::Vector3d r = s.x[static_cast<std::size_t>(j)] - s.x[static_cast<std::size_t>(i)];
      const double d2 = r.squaredNorm() + eps2;
      const Eigen::Vector3d f = s.G * r / (d2 * std::sqrt(d2));
      a[static_cast<std::size_t>(i)] += s.m[static_cast<std::size_t>(j)] * f;
      a[static_cast<std::size_t>(j)] -= s.m[static_cast<std::size_t>(i)] * f;
    }
}

// Kick-drift-kick: v += h/2 a; x += h v; v += h/2 a(x).
void leapfrog(NBodySystem& s, double h, std::vector<Eigen::Vector3d>& a) {
  accelerations(s, a);
  for (int i = 0; i < s.size(); ++i)
    if (moves(s, i)) s.v[static_cast<std::size_t>(i)] += 0.5 * h * a[static_cast<std::size_t>(i)];
  for (int i = 0; i < s.size(); ++i)
    if (moves(s, i)) s.x[static_cast<std::size_t>(i)] += h * s.v[static_cast<std::size_t>(i)];
  accelerations(s, a);
  for (int i = 0; i < s.size(); ++i)
    if (moves(s, i)) s.v[static_cast<std::size_t>(i)] += 0.5 * h * a[static_cast<std::size_t>(i)];
}

void detect_landing(NBodySystem& s) {
  if (!(s.central_radius > 0)) return;
  for (int i = 1; i < s.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (s.landed[k]) continue;
    const Eigen::Vector3d r = s.x[k] - s.x[0];
    const double d = r.norm();
    if (d <= s.central_radius) {
      s.landed[k] = 1;
      s.landed_time[k] = s.time;
      // Rests on the surface, moving with the central body.
      s.x[k] = s.x[0] + (d > 0 ? Eigen::Vector3d(r / d) : Eigen::Vector3d::UnitX()) * s.central_radius;
      s.v[k] = s.v[0];
    }
  }
}

}  // namespace

void NBodySystem::prepare() {
  const std::size_t n = x.size();
  if (n == 0) throw Error("no bodies: give at least one mass with its position and velocity");
  if (v.size() != n || m.size() != n)
    throw Error("masses, positions and velocities must have the same length (" +
                std::to_string(m.size()) + ", " + std::to_string(n) + ", " +
                std::to_string(v.size()) + ")");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(m[i] >= 0) || !std::isfinite(m[i])) throw Error("masses must be finite and non-negative");
    if (!x[i].allFinite() || !v[i].allFinite())
      throw Error("positions and velocities must be finite");
  }
  if (!(G > 0) || !std::isfinite(G)) throw Error("G must be positive");
  if (!(softening >= 0)) throw Error("softening must be non-negative");
  landed.assign(n, 0);
  landed_time.assign(n, -1.0);
  if (fixed_central) v[0].setZero();
  detect_landing(*this);
}

void step(NBodySystem& s, double h, Integrator integrator) {
  thread_local std::vector<Eigen::Vector3d> a;
  if (integrator == Integrator::leapfrog) {
    leapfrog(s, h, a);
  } else {
    // Yoshida (1990): w1 = 1/(2 − 2^{1/3}), w0 = −2^{1/3} w1; steps w1 h, w0 h, w1 h.
    const double cbrt2 = std::cbrt(2.0);
    const double w1 = 1 / (2 - cbrt2), w0 = -cbrt2 * w1;
    leapfrog(s, w1 * h, a);
    leapfrog(s, w0 * h, a);
    leapfrog(s, w1 * h, a);
  }
  s.time += h;
  detect_landing(s);
}

double total_energy(const NBodySystem& s) {
  double e = 0;
  const double eps2 = s.softening * s.softening;
  for (int i = 0; i < s.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (s.landed[k]) continue;
    if (moves(s, i)) e += 0.5 * s.m[k] * s.v[k].squaredNorm();
    for (int j = i + 1; j < s.size(); ++j) {
      const auto l = static_cast<std::size_t>(j);
      if (s.landed[l]) continue;
      e -= s.G * s.m[k] * s.m[l] / std::sqrt((s.x[l] - s.x[k]).squaredNorm() + eps2);
    }
  }
  return e;
}

double escape_speed(double G, double M, double r) { return std::sqrt(2 * G * M / r); }

}  // namespace loom::mpm
