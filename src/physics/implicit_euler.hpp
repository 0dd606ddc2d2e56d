#pragma once
// Implicit (backward) Euler as minimisation of the incremental potential (Gast et al. 2015):
//   x_{n+1} = argmin  1/(2h^2) |x - x_hat|^2_M + E(x) + D(x),   x_hat = x_n + h v_n,
// with E the potential (elastic terms, gravity) and D the damping terms' dissipation potential;
// then v_{n+1} = (x_{n+1} - x_n)/h. Newton's method with a backtracking (Armijo) line search on
// the incremental potential (which may also stretch a full step, see max_step_expansion) and a
// sparse solve: conjugate gradient on the element-wise
// PSD-projected Hessian, or supernodal Cholesky on the exact Hessian wherever that is positive
// definite (the projected one where it is not).
#include <vector>

#include "physics/cloth.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/conjugate_gradient.hpp"
#include "physics/contact_penalty.hpp"
#include "physics/newton_tail.hpp"
#include "physics/solve_contact.hpp"
#include "physics/sparse_hessian.hpp"
#include "physics/supernodal_cholesky.hpp"

namespace weft {

enum class LinearSolverKind { conjugate_gradient, cholesky };

struct ImplicitEulerSettings {
  // m/s: converged when the residual (newton_residual()) is below this: no free vertex's
  // unbalanced force would change its velocity by more than this over the step. The length of
  // the Newton step never decides convergence: a too-stiff model makes it short far from the
  // answer.
  double newton_tolerance = 1e-5;
  int max_newton_iterations = 30;
  // When the full Newton step is taken and the quadratic through Phi(x), its slope and
  // Phi(x + dx) puts the minimum along dx beyond 1.5 dx (the model over-estimated the curvature:
  // a cloth buckling, whose negative curvature the PSD projection drops), the step is stretched
  // to that minimum, at most this many times dx, if Phi is lower there. 1 turns it off.
  double max_step_expansion = 4.0;
  LinearSolverKind linear_solver = LinearSolverKind::conjugate_gradient;
  // Conjugate gradient stops at a relative residual eta_k that tightens as Newton converges
  // (Eisenstat and Walker's forcing term): eta_0 = cg_initial_tolerance, then
  // eta_k = (|g_k| / |g_{k-1}|)^2, clamped to [cg_tolerance, cg_initial_tolerance].
  double cg_tolerance = 1e-6;
  double cg_initial_tolerance = 1e-2;
  int max_cg_iterations = 2000;
  // CG's preconditioner (physics/conjugate_gradient.hpp).
  Preconditioner cg_preconditioner = Preconditioner::symmetric_gauss_seidel;
  // With conjugate gradient, once at most this share of the free vertices is above the tolerance
  // the next iterations work on those vertices and their neighbours only (physics/newton_tail.hpp;
  // models it supports, no contact penalty); 0 turns it off.
  double restricted_tail_share = 0.02;
  // With conjugate gradient, the dihedral hinges' Hessian is left out of Newton's matrix while
  // h^2 bending_stiffness_rate() (physics/bending.hpp: their share of m/h^2 on a vertex's diagonal
  // at rest) is below this. The energy and the gradient keep them, so the answer and the residual
  // are the same; the matrix is cheaper (a block row of the grid ~13 blocks with the hinges' wing
  // tips, ~7 without) and further from the Hessian. Below the threshold leaving them out is
  // faster; well above it Newton and CG need more iterations than the cheaper matrix saves
  // (docs/integrators.md, "Which linear solver inside implicit Euler"). 0 keeps them always.
  double bending_hessian_share = 0.75;
  // A step without the hinges in the matrix that has not converged after this many Newton
  // iterations goes on with them (the matrix with them is kept prepared beside): where a cloth
  // folds over an edge or lies on another, the matrix without them stalls Newton. How the count
  // was chosen: docs/integrators.md, same section.
  int hinges_out_of_matrix_iterations = 6;
  // Fills NewtonReport::iterations (weft --newton-log): one more pass over the vertices an
  // iteration, to count those above the tolerance.
  bool record_iterations = false;
};

// One Newton iteration of a step, as --newton-log writes it (docs/recording.md). Record 0 is the
// step's start (the inertial predictor): its step_scale and linear_iterations are 0.
struct NewtonIterationRecord {
  double residual = 0.0;          // m/s, newton_residual() after the iteration
  int above_tolerance = 0;        // free vertices whose h |g_i| / m_i is above the tolerance after it
  double step_scale = 0.0;        // the multiple of the Newton step taken (line search; > 1 stretched)
  int linear_iterations = 0;      // CG iterations of this iteration's solve (0 for Cholesky)
  int restricted_iterations = 0;  // Newton tail iterations that followed it (its residual is after them)
};

// What the last step did. The step ends at the iterate with the smallest residual it reached.
struct NewtonReport {
  int newton_iterations = 0;
  int linear_iterations = 0;           // CG iterations summed over Newton iterations (0 for Cholesky)
  bool converged = false;              // the residual fell below newton_tolerance
  double residual = 0.0;               // m/s, newton_residual() at the step's end
  int projected_hessians = 0;          // Cholesky only: iterations whose exact Hessian was not positive
                                       // definite, so the element-wise projected one was solved instead
  int stretched_steps = 0;             // Newton steps the line search stretched past dx (max_step_expansion)
  int restricted_iterations = 0;       // of newton_iterations, those restricted to the tail's region
  int diverged_stops = 0;              // 1 when the step stopped with the residual far above its best
                                       // for several iterations (the best iterate is returned)
  int full_matrix_steps = 0;           // 1 when the step began without the hinges' Hessian in the
                                       // matrix and went on with it (hinges_out_of_matrix_iterations)
  std::vector<double> gradient_norms;  // |grad of incremental potential| over free vertices, per iteration
  // With ImplicitEulerSettings::record_iterations: the start, then one record per global
  // iteration; empty otherwise.
  std::vector<NewtonIterationRecord> iterations;
};

// The residual of the incremental potential's gradient g (N per vertex, pinned entries zero) in
// the units of velocity: max over vertices of h |g_i| / m_i, the velocity change the unbalanced
// force on vertex i would cause over the step. Zero exactly at the implicit Euler solution.
double newton_residual(const Positions& gradient, const Eigen::VectorXd& inverse_mass, double h);

// How many vertices have their share h |g_i| / m_i above `tolerance`, computed as newton_residual()
// computes it (so the count is 0 exactly when newton_residual() <= tolerance).
int vertices_above_tolerance(const Positions& gradient, const Eigen::VectorXd& inverse_mass, double h,
                             double tolerance);

// newton_residual() at the start of a step (the inertial predictor) of a cloth at rest in its rest
// shape, under gravity alone: |gravity| h. A newton_tolerance at or above it accepts a step whose
// vertices are off by gravity's whole pull over it; the scene file refuses such a tolerance and
// the viewer's Solver panel warns.
double resting_start_residual(const Vec3& gravity, double h);

// A step's last evaluation of the incremental potential with a gradient, in the parts the energy
// ledger needs at the step's end (sim/energy_ledger.hpp), which would otherwise take another pass
// over the elements there.
struct IncrementalPotentialParts {
  Positions point;         // where it was evaluated
  double potential = 0.0;  // U: the elastic terms and gravity
  double penalty = 0.0;    // the contact penalty's energy (0 without one)
  // With a SolveContact: its energy's gradient (barrier and friction), and its potential part
  // (the barrier); zero and empty without one.
  double contact_potential = 0.0;
  Positions contact_gradient;
  Positions gradient;  // grad Phi = M (x - x_hat) / h^2 + grad U + grad D + grad penalty, pinned rows kept
};

// Preallocated storage for one cloth's implicit steps; the sparsity pattern is built on first use.
class ImplicitEulerSolver {
 public:
  // Advances the cloth by h. Returns the report (also kept in last_report()). `penalty`, when
  // given and active, adds its contact energy to the incremental potential; with the Cholesky
  // solver only its diagonal blocks enter the matrix (its coupling blocks are not in the pattern).
  // `contact`, when given, adds contact inside the solve (physics/solve_contact.hpp): its energy
  // joins the incremental potential, the predictor and every Newton step stop where it bounds
  // them, and pinned vertices reach their targets through the Newton steps (so that a bounded
  // predictor leaves none behind); the step converges only with every pin on its target.
  const NewtonReport& step(Cloth& cloth, const Vec3& gravity, double h, const ImplicitEulerSettings& settings,
                           const ContactPenalty* penalty = nullptr, SolveContact* contact = nullptr);
  const NewtonReport& last_report() const { return report_; }
  // The last step's last evaluation with a gradient when it was taken at exactly `x` (the
  // cloth's positions as the step left them, unless something moved them since); else null.
  const IncrementalPotentialParts* last_evaluation_at(const Positions& x) const;

 private:
  void prepare(const ClothModel& model, bool hinges_in_matrix);
  double incremental_potential(const ClothModel& model, const Vec3& gravity, const Positions& x, double h,
                               Positions* gradient, bool assemble, bool project);
  bool solve(const ImplicitEulerSettings& settings, double cg_tolerance, const Eigen::VectorXd* cg_guess);
  void swap_patterns();  // hessian_ / stencils_ with full_hessian_ / full_stencils_

  const ContactPenalty* penalty_ = nullptr;     // during step()
  SolveContact* contact_ = nullptr;             // during step()
  ContactBlocks contact_blocks_;                // its Hessian at x_linearized_
  bool contact_coupled_ = false;                // contact_blocks_ has blocks off the pattern
  bool cholesky_in_use_ = false;                // during step(): the matrix alone is solved
  Positions contact_gradient_;                  // its gradient at the last evaluation
  Positions pin_targets_;                       // with contact_: x_hat (where every pin ends)
  Positions zero_motion_;                       // zeros (3 x n)
  ConjugateGradientSolver::Coupling coupling_;  // penalty coupling blocks at x_linearized_
  Positions x_linearized_;                      // where the Hessian was last assembled
  bool prepared_ = false;
  bool hinges_in_matrix_ = true;  // false: the hinges' Hessian starts each step out of the matrix
  double bending_rate_ = 0.0;     // bending_stiffness_rate() of the model (1/s^2), computed at
  double rate_stiffness_ = 0.0;   // this bending stiffness
  double rate_mass_ = 0.0;        // and this total mass
  int num_vertices_ = 0;
  SparseHessian hessian_;  // the matrix Newton assembles and solves
  HessianStencils stencils_;
  SparseHessian full_hessian_;  // without the hinges in the pattern: the one with them, else empty
  HessianStencils full_stencils_;
  bool hinges_out_of_matrix_ = false;  // hessian_ is the one without the hinges
  Positions x_start_, x_hat_, gradient_, trial_;
  Positions best_x_;           // the iterate with the smallest residual so far
  Eigen::VectorXd free_mask_;  // 1 for free coordinates, 0 for pinned (3n)
  Eigen::VectorXd rhs_, dx_;
  Eigen::VectorXd trial_step_;    // with contact: a stretched Newton step (3n)
  Eigen::VectorXd gravity_drop_;  // h^2 g on free coordinates: CG's guess on a step's first solve
  ConjugateGradientSolver cg_;
  SupernodalCholesky cholesky_;
  NewtonTail tail_;
  bool tail_supported_ = false;
  NewtonReport report_;
  IncrementalPotentialParts last_evaluation_;
  bool last_evaluation_valid_ = false;  // last_evaluation_ was taken in the last step
};

}  // namespace weft
