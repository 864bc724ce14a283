// The N-body integrators against Kepler's laws and the escape speed.
#include "orbits.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "loom/error.hpp"

#include <gtest/gtest.h>

namespace loom::mpm {
namespace {

// A ship around a fixed planet of mass M = 1 at the origin, G = 1, starting at
// periapsis r_p with speed v (tangential).
NBodySystem ship(double rp, double v) {
  NBodySystem s;
  s.G = 1;
  s.fixed_central = true;
  s.m = {1.0, 1e-12};
  s.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(rp, 0, 0)};
  s.v = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, v, 0)};
  s.prepare();
  return s;
}

// The time of the first crossing of y = 0 from below after t = 0, located by
// bisection on the step length from the step that crosses it.
double period(NBodySystem s, double h, Integrator integrator) {
  for (;;) {
    NBodySystem before = s;
    step(s, h, integrator);
    if (before.x[1][1] < 0 && s.x[1][1] >= 0) {
      double lo = 0, hi = h;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        NBodySystem t = before;
        step(t, mid, integrator);
        (t.x[1][1] < 0 ? lo : hi) = mid;
      }
      return before.time + 0.5 * (lo + hi);
    }
  }
}

TEST(Orbits, KeplersThirdLaw) {
  // Ellipses of semi-major axis a from periapsis 1: v_p = √((2/r_p − 1/a)) (vis-viva).
  for (double a : {1.0, 1.5, 2.5, 4.0}) {
    const double rp = 1;
    const auto s = ship(rp, std::sqrt(2 / rp - 1 / a));
    const double T = period(s, 2 * M_PI * std::pow(a, 1.5) / 20000, Integrator::yoshida4);
    // T² = 4π² a³ / (G M)
    const double ratio = T * T / (4 * M_PI * M_PI * a * a * a);
    std::printf("a = %g: T²/(4π² a³) − 1 = %.3g\n", a, ratio - 1);
    EXPECT_NEAR(ratio, 1.0, 1e-6) << "a = " << a;
  }
}

// Max relative energy error over `orbits` orbits of an e = 0.5 ellipse.
double energy_error(Integrator integrator, double steps_per_orbit, int orbits,
                    double* first = nullptr, double* last = nullptr) {
  const double a = 2;  // r_p = 1, e = 0.5
  auto s = ship(1, std::sqrt(2 - 1 / a));
  const double T = 2 * M_PI * std::pow(a, 1.5), h = T / steps_per_orbit;
  const double e0 = total_energy(s);
  double worst = 0, worst_first = 0, worst_last = 0;
  const long steps = static_cast<long>(steps_per_orbit) * orbits;
  for (long k = 0; k < steps; ++k) {
    step(s, h, integrator);
    const double err = std::abs(total_energy(s) - e0) / std::abs(e0);
    worst = std::max(worst, err);
    if (k < steps / 10) worst_first = std::max(worst_first, err);
    if (k >= steps - steps / 10) worst_last = std::max(worst_last, err);
  }
  if (first) *first = worst_first;
  if (last) *last = worst_last;
  return worst;
}

TEST(Orbits, LeapfrogEnergyBoundedOver10000Orbits) {
  double first = 0, last = 0;
  const double worst = energy_error(Integrator::leapfrog, 200, 10000, &first, &last);
  std::printf("leapfrog, 10^4 orbits: max |ΔE/E| %.3g (first tenth %.3g, last tenth %.3g)\n",
              worst, first, last);
  // No secular drift: the last thousand orbits are no worse than the first.
  EXPECT_LT(last, 1.05 * first);
  EXPECT_LT(worst, 1e-2);
}

double slope(Integrator integrator) {
  const double e1 = energy_error(integrator, 400, 10), e2 = energy_error(integrator, 800, 10);
  return std::log2(e1 / e2);
}

TEST(Orbits, EnergyErrorConvergesAsH2AndH4) {
  const double leapfrog = slope(Integrator::leapfrog), yoshida = slope(Integrator::yoshida4);
  std::printf("energy error slopes: leapfrog %.3f, Yoshida %.3f\n", leapfrog, yoshida);
  EXPECT_NEAR(leapfrog, 2, 0.1);
  EXPECT_NEAR(yoshida, 4, 0.2);
}

// Kepler's equation M = E − e sin E, by Newton.
Eigen::Vector2d kepler_position(double a, double e, double mu, double t) {
  const double n = std::sqrt(mu / (a * a * a));
  const double M = n * t;
  double E = M;
  for (int k = 0; k < 50; ++k) E -= (E - e * std::sin(E) - M) / (1 - e * std::cos(E));
  return {a * (std::cos(E) - e), a * std::sqrt(1 - e * e) * std::sin(E)};
}

TEST(Orbits, TwoBodyOrbitMatchesKepler) {
  // Two free bodies; their separation follows a Kepler ellipse with μ = G (m1 + m2).
  NBodySystem s;
  s.G = 1;
  s.m = {1.0, 0.3};
  const double mu = s.G * 1.3, a = 1.5, e = 0.4, rp = a * (1 - e);
  const double vp = std::sqrt(mu * (1 + e) / rp);
  // Centre of mass at rest at the origin.
  s.x = {Eigen::Vector3d(-rp * 0.3 / 1.3, 0, 0), Eigen::Vector3d(rp * 1.0 / 1.3, 0, 0)};
  s.v = {Eigen::Vector3d(0, -vp * 0.3 / 1.3, 0), Eigen::Vector3d(0, vp * 1.0 / 1.3, 0)};
  s.prepare();
  const double T = 2 * M_PI * std::sqrt(a * a * a / mu), h = T / 5000;
  double worst = 0;
  for (int k = 1; k <= 5000 * 3; ++k) {
    step(s, h, Integrator::yoshida4);
    const Eigen::Vector3d r = s.x[1] - s.x[0];
    const Eigen::Vector2d ref = kepler_position(a, e, mu, k * h);
    worst = std::max(worst, (r.head<2>() - ref).norm() / a);
  }
  std::printf("two-body vs Kepler over 3 orbits: max position error / a = %.3g\n", worst);
  EXPECT_LT(worst, 1e-8);
}

// Bound or not, decided from the trajectory: it turns back (ṙ < 0) before
// reaching 10⁶ radii. Step h ∝ r^{3/2} (a constant fraction of the local
// orbital time) keeps the far flight short.
bool escapes(double v) {
  auto s = ship(1, 0);
  s.v[1] = Eigen::Vector3d(v, 0, 0);  // straight up, radially
  for (;;) {
    const double r = s.x[1].norm();
    if (s.x[1].dot(s.v[1]) < 0) return false;
    if (r > 1e6) return true;
    step(s, 1e-3 * std::pow(r, 1.5), Integrator::yoshida4);
  }
}

TEST(Orbits, EscapeThreshold) {
  double lo = 0.5 * std::sqrt(2.0), hi = 2 * std::sqrt(2.0);
  ASSERT_FALSE(escapes(lo));
  ASSERT_TRUE(escapes(hi));
  while (hi - lo > 1e-6) {
    const double mid = 0.5 * (lo + hi);
    (escapes(mid) ? hi : lo) = mid;
  }
  const double found = 0.5 * (lo + hi), exact = escape_speed(1, 1, 1);
  std::printf("escape threshold %.8f vs √(2GM/r) %.8f: relative %.3g\n", found, exact,
              found / exact - 1);
  EXPECT_NEAR(found / exact, 1, 1e-4);
}

TEST(Orbits, LandingEventAndSoftening) {
  auto s = ship(2, 0.3);  // falls onto a planet of radius 1
  s.central_radius = 1;
  s.prepare();
  for (int k = 0; k < 100000 && !s.landed[1]; ++k) step(s, 1e-3, Integrator::leapfrog);
  ASSERT_TRUE(s.landed[1]);
  EXPECT_NEAR(s.x[1].norm(), 1, 1e-12);
  EXPECT_GT(s.landed_time[1], 0);
  // Softening bounds the force: a close pass through the centre stays finite.
  auto t = ship(1, 0);
  t.softening = 0.1;
  for (int k = 0; k < 10000; ++k) step(t, 1e-3, Integrator::leapfrog);
  EXPECT_TRUE(t.x[1].allFinite() && t.v[1].allFinite());
}

// Massless bodies attract nothing: three ships launched from one point each
// follow exactly the path they follow alone (the reference: one run per ship).
TEST(Orbits, MasslessBodiesAtOnePointFlyIndependently) {
  const std::vector<double> speeds = {0.8, 1.0, 1.3};
  NBodySystem together;
  together.fixed_central = true;
  together.m = {1.0, 0.0, 0.0, 0.0};
  together.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0)};
  together.v = {Eigen::Vector3d::Zero()};
  for (double v : speeds) together.v.emplace_back(0, v, 0);
  together.prepare();
  for (int k = 0; k < 2000; ++k) step(together, 1e-3, Integrator::yoshida4);
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    NBodySystem alone;
    alone.fixed_central = true;
    alone.m = {1.0, 0.0};
    alone.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0)};
    alone.v = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, speeds[i], 0)};
    alone.prepare();
    for (int k = 0; k < 2000; ++k) step(alone, 1e-3, Integrator::yoshida4);
    ASSERT_TRUE(together.x[i + 1].allFinite());
    EXPECT_EQ(together.x[i + 1], alone.x[1]) << "ship " << i + 1;
    EXPECT_EQ(together.v[i + 1], alone.v[1]) << "ship " << i + 1;
  }
}

// Two bodies at one point of which one has mass: an error naming both.
TEST(Orbits, CoincidentMassiveBodiesAreAnErrorNamingThem) {
  for (const std::vector<double>& masses : {std::vector<double>{1.0, 0.5, 0.5}, std::vector<double>{1.0, 0.0, 0.5}}) {
    NBodySystem s;
    s.fixed_central = false;
    s.m = masses;
    s.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 2, 3)};
    s.v = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0)};
    try {
      s.prepare();
      ADD_FAILURE() << "coincident bodies with mass accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bodies 1 and 2"), std::string::npos) << e.what();
    }
    s.softening = 0.01;  // a softened attraction is finite
    EXPECT_NO_THROW(s.prepare());
  }
}

// A ship's specific orbital energy about the planet, against the analytic
// value of a circular orbit (ε = −GM/(2r)), and its drift: Yoshida's is
// fourth order in h.
TEST(Orbits, SpecificEnergyOfAShip) {
  NBodySystem s;
  s.fixed_central = true;
  s.m = {2.0, 0.0};
  s.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 0, 0)};
  s.v = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0)};  // circular: v² = GM/r = 1
  s.prepare();
  ASSERT_TRUE(s.central_only_mass());
  EXPECT_NEAR(specific_energy(s, 1), -0.5, 1e-15);
  EXPECT_NEAR(specific_energy_scale(s, 1), 1.5, 1e-15);
  s.x[1] = Eigen::Vector3d(0.5, 0, 0);  // from an ellipse's periapsis the drift is not zero
  s.v[1] = Eigen::Vector3d(0, 2.2, 0);
  auto drift = [&](double h) {
    NBodySystem t = s;
    const double e0 = specific_energy(t, 1);
    double worst = 0;
    for (int k = 0; k < static_cast<int>(std::lround(6 / h)); ++k) {
      step(t, h, Integrator::yoshida4);
      worst = std::max(worst, std::abs(specific_energy(t, 1) - e0));
    }
    return worst;
  };
  const double coarse = drift(0.01), fine = drift(0.005);
  std::printf("ship specific energy drift %.3g (h = 0.01), %.3g (h = 0.005): order %.2f\n", coarse, fine,
              std::log2(coarse / fine));
  EXPECT_GT(coarse, 0);
  EXPECT_NEAR(std::log2(coarse / fine), 4, 0.3);
}

// Radial fall from rest at r0 onto a body of radius R (GM = 1): the landing
// time in closed form, t = √(r0³/2GM) (√(ξ(1 − ξ)) + arccos √ξ), ξ = R/r0,
// located inside the step however coarse the step.
TEST(Orbits, LandingTimeIsLocatedInsideTheStep) {
  const double r0 = 2, R = 1, xi = R / r0;
  const double exact = std::sqrt(r0 * r0 * r0 / 2) * (std::sqrt(xi * (1 - xi)) + std::acos(std::sqrt(xi)));
  for (double h : {0.1, 0.03, 0.01}) {
    NBodySystem s;
    s.fixed_central = true;
    s.m = {1.0, 0.0};
    s.x = {Eigen::Vector3d::Zero(), Eigen::Vector3d(r0, 0, 0)};
    s.v = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    s.central_radius = R;
    s.prepare();
    int steps = 0;
    while (!s.landed[1]) {
      step(s, h, Integrator::yoshida4);
      ++steps;
    }
    std::printf("h = %g: landed at %.9f, exact %.9f (error %.2g; the step's end %.6f was %.2g late)\n", h,
                s.landed_time[1], exact, s.landed_time[1] - exact, s.time, s.time - exact);
    EXPECT_NEAR(s.landed_time[1], exact, 1e-3 * h);
    EXPECT_NEAR(s.x[1].norm(), R, 1e-12);
  }
}

}  // namespace
}  // namespace loom::mpm
