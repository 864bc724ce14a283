#include "time_step.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "incremental_potential.hpp"
#include "loom/error.hpp"

namespace loom::cloth {

ClothState rest_state(std::shared_ptr<const SpringSystem> system) {
  ClothState state;
  state.x = system->X;
  state.v = Eigen::MatrixX3d::Zero(system->X.rows(), 3);
  state.system = std::move(system);
  return state;
}

double max_frequency(const SpringSystem& s) {
  Eigen::VectorXd k_sum = Eigen::VectorXd::Zero(s.vertices());
  for (Eigen::Index k = 0; k < s.springs.rows(); ++k) {
    k_sum[s.springs(k, 0)] += s.stiffness[k];
    k_sum[s.springs(k, 1)] += s.stiffness[k];
  }
  double w2 = 0;
  for (int i = 0; i < s.vertices(); ++i)
    if (!s.fixed[i] && s.mass[i] > 0) w2 = std::max(w2, 2 * k_sum[i] / s.mass[i]);
  return std::sqrt(w2);
}

Eigen::MatrixX3d external_forces(const SpringSystem& s, const Eigen::MatrixX3d& x,
                                 const Eigen::MatrixX3d& v, double t, const StepSettings& settings) {
  Eigen::MatrixX3d f = s.mass * settings.gravity.transpose();
  const double wn = settings.wind_direction.norm();
  if (settings.wind_speed == 0 || wn == 0 || s.F.rows() == 0) return f;
  const Eigen::Vector3d dir = settings.wind_direction / wn;
  // Three travelling waves with seeded frequencies, wave vectors and phases.
  std::mt19937_64 rng(settings.seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  struct Wave {
    double omega, phase;
    Eigen::Vector3d kappa;
  } waves[3];
  for (auto& w : waves) {
    w.omega = 1 + 3 * uniform(rng);
    w.phase = 2 * M_PI * uniform(rng);
    w.kappa = Eigen::Vector3d(uniform(rng) - 0.5, uniform(rng) - 0.5, uniform(rng) - 0.5) * 6;
  }
  // Area-weighted vertex normals and area shares at x.
  Eigen::MatrixX3d normal = Eigen::MatrixX3d::Zero(x.rows(), 3);
  for (Eigen::Index t3 = 0; t3 < s.F.rows(); ++t3) {
    const Eigen::RowVector3d a = x.row(s.F(t3, 0)), b = x.row(s.F(t3, 1)), c = x.row(s.F(t3, 2));
    const Eigen::RowVector3d n2 = (b - a).cross(c - a);  // twice the area along the normal
    for (int k = 0; k < 3; ++k) normal.row(s.F(t3, k)) += n2;
  }
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double len = normal.row(i).norm();
    if (len == 0 || s.fixed[i]) continue;
    const Eigen::RowVector3d n = normal.row(i) / len;
    const double area = len / 6;
    double eta = 0;
    for (const auto& w : waves) eta += std::sin(w.omega * t + w.kappa.dot(s.X.row(i).transpose()) + w.phase) / 3;
    const Eigen::RowVector3d wind = settings.wind_speed * (1 + settings.turbulence * eta) * dir.transpose();
    f.row(i) += area * (wind - v.row(i)).dot(n) * n;
  }
  return f;
}

double contact_weight(const SpringSystem& s) {
  return 0.1 * std::max(1.0, s.stiffness.size() > 0 ? s.stiffness.maxCoeff() : 1.0);
}

namespace {

// Projects x out of the colliders; returns the outward normal per vertex that
// touched one (zero otherwise). A vertex whose path from x_n entered a sphere
// is pushed onto the tangent plane at the point where it came from (the
// normal of x_n), not radially: a step that carries it past the center would
// otherwise push it out of the far side.
// `friction`: apply Coulomb friction where vertices are pushed out (false
// for Newton, whose friction is in its solve: friction_potential).
Eigen::MatrixX3d resolve_collisions(const SpringSystem& s, const Eigen::MatrixX3d& x_n,
                                    Eigen::MatrixX3d& x, const StepSettings& settings, bool friction = true) {
  Eigen::MatrixX3d contact = Eigen::MatrixX3d::Zero(x.rows(), 3);
  if (!settings.ground && settings.spheres.empty()) return contact;
  // Coulomb friction on positions (as position-based dynamics does it): a
  // vertex pushed out by `depth` along n keeps its tangential motion since x_n
  // only beyond friction·depth (static below that, kinetic above).
  auto rub = [&](Eigen::Index i, const Eigen::RowVector3d& n, double depth) {
    if (!friction || settings.friction <= 0 || depth <= 0) return;
    const Eigen::RowVector3d moved = x.row(i) - x_n.row(i);
    const Eigen::RowVector3d tangential = moved - moved.dot(n) * n;
    const double slide = tangential.norm(), limit = settings.friction * depth;
    x.row(i) -= slide <= limit ? tangential : Eigen::RowVector3d(tangential * (limit / slide));
  };
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (s.fixed[i]) continue;
    for (const auto& sphere : settings.spheres) {
      const Eigen::RowVector3d c = sphere.center.transpose();
      // Inside, or passed through within this step (the segment from x_n
      // comes closer to the center than the radius): stiff springs can carry
      // a vertex across a whole sphere in one iteration.
      const Eigen::RowVector3d path = x.row(i) - x_n.row(i);
      const double along = path.squaredNorm() > 0
                               ? std::clamp((c - x_n.row(i)).dot(path) / path.squaredNorm(), 0.0, 1.0)
                               : 1.0;
      if ((x_n.row(i) + along * path - c).norm() >= sphere.radius) continue;
      // x_n lies on or outside the sphere (it was projected last step), up
      // to rounding: its normal is where the vertex came from.
      const Eigen::RowVector3d from = x_n.row(i) - c;
      Eigen::RowVector3d n = from.norm() > 0 ? Eigen::RowVector3d(from.normalized()) : Eigen::RowVector3d(0, 1, 0);
      const double depth = sphere.radius - (x.row(i) - c).dot(n);
      x.row(i) += depth * n;
      rub(i, n, depth);
      const double after = (x.row(i) - c).norm();
      if (after < sphere.radius) x.row(i) = c + sphere.radius * (x.row(i) - c) / after;
      contact.row(i) = n;
    }
    if (settings.ground && x(i, 1) < settings.ground_height) {
      const double depth = settings.ground_height - x(i, 1);
      x(i, 1) = settings.ground_height;
      contact.row(i) << 0, 1, 0;
      rub(i, contact.row(i), depth);
    }
  }
  return contact;
}

double contact_stiffness(const SpringSystem& s) {
  return 1e3 * std::max(1.0, s.stiffness.size() > 0 ? s.stiffness.maxCoeff() : 1.0);
}

// Contact as a penalty for Newton: P = ½ κ Σ d² over penetration depths d
// (ground: height − y; sphere: r − ‖x − c‖), Hessian blocks κ n nᵀ (the
// sphere's curvature term left out, so the blocks stay semidefinite). κ is
// 1000 times the stiffest spring: a resting body sinks by its weight / κ, and
// the projection after the step removes that.
double contact_penalty(const SpringSystem& s, const StepSettings& settings, const Eigen::MatrixX3d& x,
                       Eigen::MatrixX3d* gradient, std::vector<std::pair<int, Eigen::Matrix3d>>* blocks) {
  const double kappa = contact_stiffness(s);
  double p = 0;
  auto add = [&](Eigen::Index i, double depth, const Eigen::RowVector3d& n) {
    p += 0.5 * kappa * depth * depth;
    if (gradient) gradient->row(i) -= kappa * depth * n;
    if (blocks) blocks->emplace_back(static_cast<int>(i), kappa * n.transpose() * n);
  };
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (s.fixed[i]) continue;
    if (settings.ground && x(i, 1) < settings.ground_height)
      add(i, settings.ground_height - x(i, 1), Eigen::RowVector3d(0, 1, 0));
    for (const auto& sphere : settings.spheres) {
      const Eigen::RowVector3d d = x.row(i) - sphere.center.transpose();
      const double len = d.norm();
      if (len < sphere.radius && len > 0) add(i, sphere.radius - len, d / len);
    }
  }
  return p;
}

// Coulomb friction for Newton, inside the minimization (as IPC does it: Li et
// al. 2020, §5): a lagged dissipative potential
//   D = Σ_c μ λ_c f0(‖u_c‖),  u_c = (I − n_c n_cᵀ)(x_i − x_n,i),
// over the contacts c of the frictionless solve's solution, with their normal
// force λ_c = κ d_c and normal n_c held fixed through a second solve (one
// lagging pass; lagging them per Newton iteration instead did not converge
// and stretched the drape by 340 %). f0 is Coulomb's |u| smoothed below
// ε = ε_v h: f0(u) = −u³/(3ε²) + u²/ε + ε/3, so its force μλ f1(u) û has
// f1 = 2u/ε − u²/ε² (static friction as a very stiff drag below ε_v) and
// is μλ û above. D is convex in x and its Hessian blocks positive
// semidefinite. The springs see the friction in the same solve: the former
// friction on the projected positions after the solve put contact vertices
// back without their neighbours and ratcheted a ring of edges around the
// sphere to 16 % stretch on the test's drape (docs/cloth.md).
struct FrictionContact {
  Eigen::Index vertex;
  Eigen::RowVector3d normal;
  double force;  // λ = κ d
};

constexpr double friction_speed = 1e-3;  // ε_v in m/s

std::vector<FrictionContact> friction_contacts(const SpringSystem& s, const StepSettings& settings,
                                               const Eigen::MatrixX3d& x) {
  std::vector<FrictionContact> contacts;
  if (settings.friction <= 0) return contacts;
  const double kappa = contact_stiffness(s);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (s.fixed[i]) continue;
    if (settings.ground && x(i, 1) < settings.ground_height)
      contacts.push_back({i, Eigen::RowVector3d(0, 1, 0), kappa * (settings.ground_height - x(i, 1))});
    for (const auto& sphere : settings.spheres) {
      const Eigen::RowVector3d d = x.row(i) - sphere.center.transpose();
      const double len = d.norm();
      if (len < sphere.radius && len > 0) contacts.push_back({i, d / len, kappa * (sphere.radius - len)});
    }
  }
  return contacts;
}

double friction_potential(const std::vector<FrictionContact>& contacts, double mu, double h,
                          const Eigen::MatrixX3d& x_n, const Eigen::MatrixX3d& x, Eigen::MatrixX3d* gradient,
                          std::vector<std::pair<int, Eigen::Matrix3d>>* blocks) {
  const double eps = friction_speed * h;
  double p = 0;
  for (const FrictionContact& c : contacts) {
    const Eigen::RowVector3d moved = x.row(c.vertex) - x_n.row(c.vertex);
    const Eigen::RowVector3d u = moved - moved.dot(c.normal) * c.normal;
    const double len = u.norm(), scale = mu * c.force;
    const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - c.normal.transpose() * c.normal;
    if (len < eps) {
      p += scale * (-len * len * len / (3 * eps * eps) + len * len / eps + eps / 3);
      // f1(u)/u u = (2/ε − u/ε²) u; Hessian (2/ε − u/ε²) T − u/ε² ûûᵀ
      // (eigenvalues 2/ε − 2u/ε² ≥ 0 along û and 2/ε − u/ε² across).
      if (gradient) gradient->row(c.vertex) += scale * (2 / eps - len / (eps * eps)) * u;
      if (blocks) {
        Eigen::Matrix3d block = (2 / eps - len / (eps * eps)) * tangent;
        if (len > 0) block -= (len / (eps * eps)) * (u.transpose() / len) * (u / len);
        blocks->emplace_back(static_cast<int>(c.vertex), scale * block);
      }
    } else {
      p += scale * len;
      if (gradient) gradient->row(c.vertex) += scale / len * u;
      if (blocks) {
        const Eigen::RowVector3d dir = u / len;
        blocks->emplace_back(static_cast<int>(c.vertex),
                             scale / len * (tangent - dir.transpose() * dir).eval());
      }
    }
  }
  return p;
}

// Local/global's start (Start in time_step.hpp).
Eigen::MatrixX3d local_global_start(const SpringSystem& s, const Eigen::MatrixX3d& x_n, const Eigen::MatrixX3d& v0,
                                    const Eigen::MatrixX3d& y, double h, Start start) {
  if (start == Start::prediction) return y;
  Eigen::MatrixX3d x0 = x_n;
  for (Eigen::Index i = 0; i < x0.rows(); ++i)
    if (!s.fixed[i]) x0.row(i) += h * v0.row(i);
  if (start == Start::extrapolation) return x0;
  return incremental_potential(s, x0, y, h) < incremental_potential(s, y, y, h) ? x0 : y;
}

// v_n after the step's damping: e^{−c h} v_n.
Eigen::MatrixX3d damped_velocity(const ClothState& state, double h, const StepSettings& settings) {
  return std::exp(-settings.damping * h) * state.v;
}

}  // namespace

Eigen::MatrixX3d inertial_prediction(const ClothState& state, double h, const StepSettings& settings) {
  const SpringSystem& s = *state.system;
  const Eigen::MatrixX3d f = external_forces(s, state.x, state.v, state.time, settings);
  const Eigen::MatrixX3d v0 = damped_velocity(state, h, settings);
  Eigen::MatrixX3d y = state.x;
  for (Eigen::Index i = 0; i < y.rows(); ++i)
    if (!s.fixed[i]) y.row(i) += h * v0.row(i) + h * h / s.mass[i] * f.row(i);
  return y;
}

StepResult step(const ClothState& state, double h, const StepSettings& settings, const LocalGlobalSolver* lg,
                NewtonWorkspace* newton_workspace) {
  const SpringSystem& s = *state.system;
  StepResult result;
  result.state.system = state.system;
  result.state.time = state.time + h;
  if (h == 0) {
    result.state.x = state.x;
    result.state.v = state.v;
    return result;
  }
  const Eigen::MatrixX3d v0 = damped_velocity(state, h, settings);
  Eigen::MatrixX3d x;
  if (settings.solver == Solver::explicit_euler) {
    // Symplectic Euler: v_{n+1} = v_n + h M⁻¹ (f_ext + f_int(x_n)), x_{n+1} = x_n + h v_{n+1}.
    const Eigen::MatrixX3d force =
        external_forces(s, state.x, state.v, state.time, settings) + spring_forces(s, state.x);
    x = state.x;
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      if (!s.fixed[i]) x.row(i) += h * (v0.row(i) + h / s.mass[i] * force.row(i));
    if (!x.allFinite())
      throw Error("explicit integration diverged (positions became infinite) at t = " +
                  std::to_string(state.time) + " s: h = " + std::to_string(h) +
                  " s exceeds the stability bound 2/ω_max = " + std::to_string(2 / max_frequency(s)) +
                  " s; use more substeps or an implicit solver");
  } else {
    const Eigen::MatrixX3d y = inertial_prediction(state, h, settings);
    SolveOptions options = settings.solve;
    std::vector<FrictionContact> friction;
    if ((settings.ground || !settings.spheres.empty()) && settings.solver == Solver::newton) {
      options.penalty = [&](const Eigen::MatrixX3d& iterate, Eigen::MatrixX3d* gradient,
                            std::vector<std::pair<int, Eigen::Matrix3d>>* blocks) {
        return contact_penalty(s, settings, iterate, gradient, blocks) +
               friction_potential(friction, settings.friction, h, state.x, iterate, gradient, blocks);
      };
    } else if ((settings.ground || !settings.spheres.empty()) && lg && lg->contact_weight() > 0)
      options.contact_target = [&](const Eigen::MatrixX3d& iterate, Eigen::MatrixX3d& target) {
        target = iterate;
        resolve_collisions(s, state.x, target, settings);
      };
    else if (settings.ground || !settings.spheres.empty())
      options.project = [&](Eigen::MatrixX3d& iterate) { resolve_collisions(s, state.x, iterate, settings); };
    if (settings.solver == Solver::newton) {
      x = newton_solve(s, y, h, y, options, &result.report, newton_workspace);
      // Friction: a second solve from there with the normal forces and
      // normals of the frictionless solution held fixed (one lagging pass).
      friction = options.penalty ? friction_contacts(s, settings, x) : std::vector<FrictionContact>();
      if (!friction.empty()) {
        SolveReport first = std::move(result.report);
        x = newton_solve(s, y, h, x, options, &result.report, newton_workspace);
        result.report.iterations += first.iterations;
        first.residuals.insert(first.residuals.end(), result.report.residuals.begin(), result.report.residuals.end());
        result.report.residuals = std::move(first.residuals);
      }
    } else {
      if (!lg || lg->h() != h || lg->free_vertices() != s.vertices() - s.fixed_count())
        throw Error("internal: the local/global solver was not factored for this system and h");
      x = lg->solve(s, y, local_global_start(s, state.x, v0, y, h, settings.start), options, &result.report);
    }
  }
  const Eigen::MatrixX3d contact = resolve_collisions(s, state.x, x, settings, settings.solver != Solver::newton);
  result.state.v = (x - state.x) / h;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    if (s.fixed[i]) {
      result.state.v.row(i).setZero();
      continue;
    }
    const double into = result.state.v.row(i).dot(contact.row(i));
    if (into < 0) result.state.v.row(i) -= into * contact.row(i);
  }
  result.state.x = std::move(x);
  return result;
}

}  // namespace loom::cloth
