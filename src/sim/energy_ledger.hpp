#pragma once
// The energy budget: where the energy a cloth gains or loses goes, measured phase by phase, so
// that at every step
//   kinetic + potential (now) + dissipated = kinetic + potential (at the start) + external work,
// with dissipated the sum of the flows below. Each flow is measured by the phase that causes it
// (docs/recording.md, "Energy budget"):
//   external work  the mouse's impulse and scripted pins' velocity changes (kinetic energy before
//                  and after), and the pins' reaction work during the solve;
//   damping        h v . F_d over the step for the damping terms and air drag, with F_d the
//                  force the integrator used (wind's work counts negative);
//   integrator     the time discretisation's own loss, from its identity (below);
//   contact        the collision phase's change of kinetic + potential energy (proximity, CCD,
//                  friction, impact zones, strain limiting; negative where a moving collider
//                  pushes the cloth) and the contact penalty's energy left at the step's end;
//   plastic        the elastic energy plastic flow releases when rest shapes follow the strain;
//   residual       an implicit Euler solve's unconverged part: minus the work of the Newton
//                  residual over the step (below), positive where the residual took energy out.
//
// The integrator's loss follows from its update rule, with U the potential (elastic, gravity and
// the contact penalty), B_U(a; b) = U(a) - U(b) - grad U(b) . (a - b) its Bregman divergence,
// dv = v1 - v0 and dx = x1 - x0:
//   implicit Euler   (M dv = h F(x1, v1)):  1/2 |dv|^2_M + B_U(x0; x1)        (>= 0 for convex U)
//   symplectic Euler (M dv = h F(x0, v0)):  1/2 |dv|^2_M - B_U(x1; x0)
// Both come from writing 1/2 |v1|^2_M - 1/2 |v0|^2_M = v1 . M dv - 1/2 |dv|^2_M and
// U(x1) - U(x0) with grad U at the end the force is taken at. For implicit Euler that leaves, with
// r = M dv / h + grad U(x1) + grad D(x1) the incremental potential's gradient at the step's end
// (zero where Newton converged), the change of energy
//   dx . r - dx . grad D(x1) - (1/2 |dv|^2_M + B_U(x0; x1)):
// r's work over a pinned vertex is the pin's (external work); over the free vertices it is the
// energy an unconverged solve added, booked as the residual flow (minus it), so that a capped
// Newton's budget closes too and says what its steps put in. Whatever is left over (a phase that
// moves the cloth without saying so) shows in the budget's error. The other integrators (midpoint
// Euler-Cromer, explicit midpoint, XPBD, adaptive sub-steps) have no such identity here: their
// whole change of energy in the solve, damping included, is booked as the integrator's, so their
// budget closes by construction and says only where energy appeared.
#include "physics/cloth.hpp"
#include "physics/contact_penalty.hpp"
#include "physics/implicit_euler.hpp"

namespace weft {

// Energy flows of one or more steps, J. External work goes into the cloths; the other five are
// dissipated (taken out; negative where a phase added energy).
struct EnergyFlows {
  double external_work = 0.0;
  double damping = 0.0;
  double integrator = 0.0;
  double contact = 0.0;
  double plastic = 0.0;
  double residual = 0.0;
  double dissipated() const { return damping + integrator + contact + plastic + residual; }
  EnergyFlows& operator+=(const EnergyFlows& other);
};

// Which identity splits a solve's change of energy (above).
enum class EnergyIdentity { implicit_euler, symplectic_euler, none };

// Kinetic energy 1/2 |v|^2_M of the cloth.
double kinetic_energy(const Cloth& cloth);

// Potential energy U of the cloth (elastic terms and gravity) at its positions.
double potential_energy(const Cloth& cloth, const Vec3& gravity);

// One cloth's solve phase: the state before the integrator runs, then the flows once it has.
class SolveLedger {
 public:
  // Records x0, v0 and U(x0) (with grad U(x0) for symplectic Euler, `need_gradient`). U(x0) is
  // the carried potential when one is held for this gravity and no gradient is asked for.
  void begin(const Cloth& cloth, const Vec3& gravity, bool need_gradient);
  // U at the cloth's positions as the collision phase left them (World measures it there for the
  // contact flow): the next begin() takes it instead of evaluating U again at the same positions,
  // unless forget_carried_potential() came in between. begin() forgets it either way; World
  // forgets it on every access that can change a cloth between steps.
  void carry_potential(double potential, const Vec3& gravity);
  void forget_carried_potential() { carried_ = false; }
  // Flows of an implicit Euler step from the recorded start to the cloth's state; `penalty`
  // as the solver saw it (null or inactive: none). `at_end`, when given, is the solver's
  // evaluation at the cloth's positions (ImplicitEulerSolver::last_evaluation_at), taken instead
  // of evaluating U, its gradient and the penalty there again.
  EnergyFlows implicit_euler(const Cloth& cloth, const Vec3& gravity, double h, const ContactPenalty* penalty,
                             const IncrementalPotentialParts* at_end = nullptr);
  // Flows of a symplectic Euler step; cloth.state.force holds the force the step used.
  EnergyFlows symplectic_euler(const Cloth& cloth, const Vec3& gravity);
  // Any other integrator: the solve's whole change of energy, booked as the integrator's.
  EnergyFlows whole_change(const Cloth& cloth, const Vec3& gravity);
  // U at the end of the last measured solve (kinetic + this is the energy the collision phase
  // starts from).
  double end_potential() const { return potential_end_; }

 private:
  Positions x0_, v0_;
  Positions dx_, dv_;     // x1 - x0, v1 - v0
  Positions gradient_;    // grad U at the start (symplectic)
  Positions row_;         // implicit: r = M dv / h + grad U(x1) + grad D(x1), penalty included,
                          // when the solver's last evaluation was not at x1
  Positions dissipation_gradient_;
  double potential_start_ = 0.0;
  double potential_end_ = 0.0;
  bool carried_ = false;
  double carried_potential_ = 0.0;
  Vec3 carried_gravity_ = Vec3::Zero();
};

}  // namespace weft
