// Gravitational N-body integration for the assignment's orbit scene:
// symplectic leapfrog (kick-drift-kick velocity Verlet) and 4th-order Yoshida
// (1990) composition, Plummer softening, an optional fixed central body and a
// "landed" event when a body reaches the central body's surface, timed inside
// the step on the step's cubic Hermite interpolant.
//
// Massless bodies (test particles: the assignment's ships) feel the others
// but attract nothing, so two of them may share a position. Two bodies at
// one position of which one has mass (and no softening) are an error naming
// them: their attraction is infinite.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace loom::mpm {

enum class Integrator { leapfrog, yoshida4 };

struct NBodySystem {
  std::vector<Eigen::Vector3d> x, v;
  std::vector<double> m;
  double G = 1;
  double softening = 0;          // ε: a = G m r / (|r|² + ε²)^{3/2}
  bool fixed_central = false;    // body 0 never moves (the assignment's planet)
  double central_radius = 0;     // > 0: bodies reaching it land on body 0
  std::vector<char> landed;      // per body
  std::vector<double> landed_time;  // per body, −1 while flying
  double time = 0;

  int size() const { return static_cast<int>(x.size()); }
  // Sizes the event arrays, checks the inputs (throws loom::Error).
  void prepare();
  // The only body with mass is body 0: then each massless body's specific
  // orbital energy about it (specific_energy) is conserved.
  bool central_only_mass() const;
};

// Advances by h (one leapfrog step, or Yoshida's three sub-steps).
void step(NBodySystem& s, double h, Integrator integrator);

// Total energy Σ ½ m v² − Σ_{i<j} G m_i m_j / √(r² + ε²) (the fixed body's
// kinetic energy is zero; landed bodies are excluded).
double total_energy(const NBodySystem& s);

// A massless body's specific orbital energy about body 0,
// ε = ½ |v − v_0|² − G m_0 / √(|x − x_0|² + ε_s²), and the scale its drift is
// measured against, ½ |v − v_0|² + G m_0 / √(…) (never 0, unlike ε at the
// escape speed).
double specific_energy(const NBodySystem& s, int body);
double specific_energy_scale(const NBodySystem& s, int body);

// The energy bookkeeping of a run: the total energy's largest relative
// drift, and when body 0 is the only mass (ships about a planet, where the
// total is 0 and says nothing) each massless body's specific-energy drift
// |ε(t) − ε(0)| / specific_energy_scale(0) until it lands.
class EnergyDrift {
 public:
  explicit EnergyDrift(const NBodySystem& s);
  void observe(const NBodySystem& s);  // after each step
  bool ships() const { return ships_; }
  double ship(int body) const { return ship_worst_[static_cast<std::size_t>(body)]; }
  // The total's drift, or with ships the largest of theirs.
  double worst() const;

 private:
  bool ships_;
  double e0_, total_worst_ = 0;
  std::vector<double> ship_e0_, ship_scale_, ship_worst_;
};

// Escape speed √(2GM/r) from distance r of mass M.
double escape_speed(double G, double M, double r);

}  // namespace loom::mpm
