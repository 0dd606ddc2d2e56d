#pragma once
// The World owns the cloths and colliders and advances them through the step pipeline
// (DESIGN.md, "One time step"). There is no global world: the caller owns each one.
#include <memory>
#include <vector>

#include "collision/collider.hpp"
#include "collision/contact_record.hpp"
#include "physics/adaptive_stepping.hpp"
#include "physics/cloth.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/integrator.hpp"
#include "physics/midpoint_euler.hpp"

namespace weft {

struct SolverSettings {
  IntegratorKind integrator = IntegratorKind::symplectic_euler;
  double time_step = 1.0 / 600.0;  // s, h of one call to World::step()
  int substeps = 1;                // integration sub-steps of h / substeps inside one step
  Vec3 gravity{0.0, -9.81, 0.0};   // m/s^2
  ImplicitEulerSettings implicit;  // Newton and linear solver (implicit_euler)
  AdaptiveSettings adaptive;       // adaptive sub-stepping (symplectic_euler, midpoint)
  int threads = 1;                 // OpenMP threads for the step (1: serial; results do not depend on it)
};

struct Energies {
  double kinetic = 0.0;
  double gravitational = 0.0;
  double elastic = 0.0;            // all elastic terms
  TermEnergies terms;              // potential energy per term
  double total() const { return kinetic + gravitational + elastic; }
};

// Wall-clock milliseconds per phase of the last World::step(), and what it found.
struct StepStats {
  double move_colliders_ms = 0.0;
  double integrate_ms = 0.0;
  double collisions_ms = 0.0;
  double rest_update_ms = 0.0;
  double total_ms = 0.0;
  int contacts = 0;
  int newton_iterations = 0;       // implicit Euler, summed over cloths and sub-steps
  int linear_iterations = 0;       // conjugate-gradient iterations, summed likewise
  int accepted_steps = 0;          // adaptive stepping: steps taken
  int rejected_steps = 0;          // adaptive stepping: steps retried smaller
  double residual = 0.0;           // implicit Euler: largest final gradient norm over cloths
  int yielded_triangles = 0;       // plasticity: triangles whose rest shape flowed

  // Sums the counts and times of `step` into this (the residual keeps the largest).
  StepStats& operator+=(const StepStats& step);
};

class World {
 public:
  SolverSettings settings;

  void add_cloth(Cloth cloth);
  void add_collider(Collider collider);

  // Advances every cloth by settings.time_step.
  void step();

  double time() const { return time_; }
  std::vector<Cloth>& cloths() { return cloths_; }
  const std::vector<Cloth>& cloths() const { return cloths_; }
  const std::vector<Collider>& colliders() const { return colliders_; }
  std::vector<Collider>& colliders() { return colliders_; }  // live edits (friction) between steps
  // External force on each vertex of cloth `cloth` (N, 3 x n_vertices, zero unless set), e.g. the
  // viewer's mouse spring. Held constant over a step and applied by every integrator as the
  // velocity impulse h f / m before it runs (exact for symplectic and implicit Euler).
  Positions& external_force(int cloth) { return external_forces_.at(static_cast<size_t>(cloth)); }
  const StepStats& last_step_stats() const { return stats_; }
  // Contacts the collision response acted on in the last sub-step of the last step(), for the
  // viewer's contact display.
  const std::vector<ContactRecord>& contacts() const { return contacts_; }
  Energies energies() const;

  // Checkpoints (io/checkpoint.hpp) save and restore what the step carries from one call to
  // the next beyond each cloth's state: the time, the colliders and the adaptive controller.
  void set_time(double time) { time_ = time; }
  AdaptiveState& adaptive_state(int cloth) { return solvers_[cloth]->adaptive; }
  const AdaptiveState& adaptive_state(int cloth) const { return solvers_[cloth]->adaptive; }

 private:
  // Per-cloth integrator storage, allocated on first use of each integrator.
  struct ClothSolvers {
    ImplicitEulerSolver implicit;
    ExplicitWorkspace explicit_workspace;
    AdaptiveState adaptive;
    ClothState trial;
  };

  void move_colliders(double h);
  void integrate(double h, StepStats& stats);
  int resolve_collisions(double h);
  int update_rest_state();
  void integrate_cloth(Cloth& cloth, ClothSolvers& solvers, double h, StepStats& stats);

  std::vector<Cloth> cloths_;
  std::vector<std::unique_ptr<ClothSolvers>> solvers_;  // Eigen solvers do not move: held by pointer
  std::vector<Collider> colliders_;
  std::vector<Positions> external_forces_;  // one per cloth (3 x n_vertices)
  std::vector<ContactRecord> contacts_;     // of the last sub-step
  double time_ = 0.0;
  StepStats stats_;
};

// How a frame of 1/fps seconds is cut into equal steps no longer than max_time_step.
struct FrameSchedule {
  int steps_per_frame = 1;
  double time_step = 0.0;          // (1/fps) / steps_per_frame
};
FrameSchedule frame_schedule(double fps, double max_time_step);

}  // namespace weft
