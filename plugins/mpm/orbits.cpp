#include "orbits.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "loom/error.hpp"

namespace loom::mpm {
namespace {

bool moves(const NBodySystem& s, int i) {
  return !(s.fixed_central && i == 0) && !s.landed[static_cast<std::size_t>(i)];
}

std::string coincident_message(const NBodySystem& s, int i, int j) {
  return "bodies " + std::to_string(i) + " and " + std::to_string(j) + " are at the same position (" +
         std::to_string(s.x[static_cast<std::size_t>(i)].x()) + ", " +
         std::to_string(s.x[static_cast<std::size_t>(i)].y()) + ", " +
         std::to_string(s.x[static_cast<std::size_t>(i)].z()) + ") at t = " + std::to_string(s.time) +
         " and one has mass: their attraction is infinite (move one, or give a softening length)";
}

void accelerations(const NBodySystem& s, std::vector<Eigen::Vector3d>& a) {
  const int n = s.size();
  a.assign(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  const double eps2 = s.softening * s.softening;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (s.landed[static_cast<std::size_t>(i)] || s.landed[static_cast<std::size_t>(j)]) continue;
      // Test particles attract nothing: two of them never interact.
      if (s.m[static_cast<std::size_t>(i)] == 0 && s.m[static_cast<std::size_t>(j)] == 0) continue;
      const Eigen::Vector3d r = s.x[static_cast<std::size_t>(j)] - s.x[static_cast<std::size_t>(i)];
      const double d2 = r.squaredNorm() + eps2;
      if (d2 == 0) throw Error(coincident_message(s, i, j));
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

// Cubic Hermite interpolant of a body's path over a step of length h from
// (x0, v0) to (x1, v1), at the fraction u in [0, 1]: exact to O(h⁴).
Eigen::Vector3d hermite(const Eigen::Vector3d& x0, const Eigen::Vector3d& v0, const Eigen::Vector3d& x1,
                        const Eigen::Vector3d& v1, double h, double u) {
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * x0 + (u3 - 2 * u2 + u) * h * v0 + (3 * u2 - 2 * u3) * x1 + (u3 - u2) * h * v1;
}

// Lands bodies that reached the central body's surface. With the step's
// start (x0, v0, length h): the landing time is the root of
// |p_i(u) − p_0(u)| = R on the Hermite interpolants (bisection, to rounding),
// not the step's end. Without (at the start): lands at s.time.
void detect_landing(NBodySystem& s, const std::vector<Eigen::Vector3d>* x0 = nullptr,
                    const std::vector<Eigen::Vector3d>* v0 = nullptr, double h = 0) {
  if (!(s.central_radius > 0)) return;
  for (int i = 1; i < s.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (s.landed[k]) continue;
    Eigen::Vector3d r = s.x[k] - s.x[0];
    if (r.norm() > s.central_radius) continue;
    double when = s.time;
    if (x0) {
      auto gap = [&](double u) -> Eigen::Vector3d {
        return hermite((*x0)[k], (*v0)[k], s.x[k], s.v[k], h, u) - hermite((*x0)[0], (*v0)[0], s.x[0], s.v[0], h, u);
      };
      double lo = 0, hi = 1;  // |gap(lo)| > R >= |gap(hi)|
      for (int it = 0; it < 60 && hi - lo > 1e-16; ++it) {
        const double mid = 0.5 * (lo + hi);
        (gap(mid).norm() > s.central_radius ? lo : hi) = mid;
      }
      when = s.time - (1 - hi) * h;
      r = gap(hi);
    }
    s.landed[k] = 1;
    s.landed_time[k] = when;
    // Rests on the surface where it touched down, moving with the central body.
    const double d = r.norm();
    s.x[k] = s.x[0] + (d > 0 ? Eigen::Vector3d(r / d) : Eigen::Vector3d::UnitX()) * s.central_radius;
    s.v[k] = s.v[0];
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
  if (softening == 0)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if ((m[i] > 0 || m[j] > 0) && !landed[i] && !landed[j] && x[i] == x[j])
          throw Error(coincident_message(*this, static_cast<int>(i), static_cast<int>(j)));
}

bool NBodySystem::central_only_mass() const {
  if (m.empty() || !(m[0] > 0)) return false;
  for (std::size_t i = 1; i < m.size(); ++i)
    if (m[i] != 0) return false;
  return true;
}

void step(NBodySystem& s, double h, Integrator integrator) {
  thread_local std::vector<Eigen::Vector3d> a, x0, v0;
  if (s.central_radius > 0) {
    x0 = s.x;
    v0 = s.v;
  }
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
  detect_landing(s, &x0, &v0, h);
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

double specific_energy(const NBodySystem& s, int body) {
  const auto k = static_cast<std::size_t>(body);
  return 0.5 * (s.v[k] - s.v[0]).squaredNorm() -
         s.G * s.m[0] / std::sqrt((s.x[k] - s.x[0]).squaredNorm() + s.softening * s.softening);
}

double specific_energy_scale(const NBodySystem& s, int body) {
  const auto k = static_cast<std::size_t>(body);
  return 0.5 * (s.v[k] - s.v[0]).squaredNorm() +
         s.G * s.m[0] / std::sqrt((s.x[k] - s.x[0]).squaredNorm() + s.softening * s.softening);
}

EnergyDrift::EnergyDrift(const NBodySystem& s)
    : ships_(s.central_only_mass()),
      e0_(total_energy(s)),
      ship_e0_(static_cast<std::size_t>(s.size()), 0),
      ship_scale_(static_cast<std::size_t>(s.size()), 1),
      ship_worst_(static_cast<std::size_t>(s.size()), 0) {
  for (int b = 1; ships_ && b < s.size(); ++b) {
    ship_e0_[static_cast<std::size_t>(b)] = specific_energy(s, b);
    ship_scale_[static_cast<std::size_t>(b)] = specific_energy_scale(s, b);
  }
}

void EnergyDrift::observe(const NBodySystem& s) {
  if (e0_ != 0) total_worst_ = std::max(total_worst_, std::abs(total_energy(s) - e0_) / std::abs(e0_));
  for (int b = 1; ships_ && b < s.size(); ++b) {
    const auto i = static_cast<std::size_t>(b);
    if (!s.landed[i])
      ship_worst_[i] = std::max(ship_worst_[i], std::abs(specific_energy(s, b) - ship_e0_[i]) / ship_scale_[i]);
  }
}

double EnergyDrift::worst() const {
  double w = total_worst_;
  for (double e : ship_worst_) w = std::max(w, e);
  return w;
}

double escape_speed(double G, double M, double r) { return std::sqrt(2 * G * M / r); }

}  // namespace loom::mpm
