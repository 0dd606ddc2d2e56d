#pragma once
// The World owns the cloths and colliders and advances them through the step pipeline
// (docs/architecture.md, "One step: `World::step()`"). There is no global world: the caller owns
// each one.
#include <array>
#include <memory>
#include <vector>

#include "collision/collider.hpp"
#include "collision/contact_record.hpp"
#include "collision/untangling.hpp"
#include "physics/adaptive_stepping.hpp"
#include "physics/cloth.hpp"
#include "physics/explicit_midpoint.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/integrator.hpp"
#include "physics/midpoint_euler_cromer.hpp"
#include "physics/xpbd.hpp"
#include "sim/collision_phase.hpp"
#include "sim/energy_ledger.hpp"
#include "sim/thread_governor.hpp"

namespace weft {

struct SolverSettings {
  IntegratorKind integrator = IntegratorKind::symplectic_euler;
  double time_step = 1.0 / 600.0;  // s, h of one call to World::step()
  int substeps = 1;                // integration sub-steps of h / substeps inside one step
  // > 0: a step whose start velocities would carry a cloth vertex farther than this many of its
  // shortest rest edges (h |v| + h^2 |g|) is cut into as many more equal sub-steps as keep every
  // vertex within it, up to max_travel_substeps (World::substeps_for_step); 0: off. A collision
  // phase handed a motion of many edge lengths a step grows impact zones over whole regions.
  double max_travel_edges = 0.0;
  Vec3 gravity{0.0, -9.81, 0.0};   // m/s^2
  ImplicitEulerSettings implicit;  // Newton and linear solver (implicit_euler)
  XpbdSettings xpbd;               // sub-steps and sweeps (xpbd)
  AdaptiveSettings adaptive;       // adaptive sub-stepping (symplectic_euler, midpoint)
  int threads = 1;                 // OpenMP threads for the step (1: serial; results do not depend on it)
  // Let the step run on one thread instead of `threads` while that measures faster (a node
  // shared with another process: sim/thread_governor.hpp). Results are the same either way.
  bool adapt_threads = true;
  CollisionSettings collision;  // the collision phase (collision_phase.hpp)
  // Measure the energy budget's flows each step (sim/energy_ledger.hpp; StepStats::energy_flows):
  // two or three potential-energy evaluations a step, one with its gradient.
  bool energy_budget = true;
};

struct Energies {
  double kinetic = 0.0;
  double gravitational = 0.0;
  double elastic = 0.0;  // all elastic terms
  TermEnergies terms;    // potential energy per term
  double total() const { return kinetic + gravitational + elastic; }
};

// Wall-clock milliseconds per phase of the last World::step(), and what it found.
struct StepStats {
  double prepare_collisions_ms = 0.0;
  double integrate_ms = 0.0;
  double collisions_ms = 0.0;
  double rest_update_ms = 0.0;
  double total_ms = 0.0;
  int steps = 0;                   // World::step() calls summed here (1 for one step)
  int substeps = 0;                // integration sub-steps taken (settings.substeps a step, or more
                                   // where settings.max_travel_edges cut it finer)
  int contacts = 0;                // contacts acted on (proximity + CCD impulses), summed over sub-steps
  // The collision phase's counts and times (impulse response), or the barrier's pairs and
  // candidates (barrier response: proximity_contacts and the candidate counts only); `clean`: every
  // sub-step ended without a detected collision (and no pin held).
  CollisionPhaseStats collision;
  int newton_iterations = 0;      // implicit Euler, summed over cloths and sub-steps
  int linear_iterations = 0;      // conjugate-gradient iterations, summed likewise
  int accepted_steps = 0;         // adaptive stepping: steps taken
  int rejected_steps = 0;         // adaptive stepping: steps retried smaller
  int unmet_tolerance_steps = 0;  // adaptive stepping: steps taken at min_step above the tolerance
  double residual = 0.0;          // implicit Euler: largest final residual over cloths and steps, m/s
                                  // (physics/implicit_euler.hpp newton_residual)
  int unconverged_steps = 0;      // implicit Euler: cloth steps that ended with the residual above
                                  // the Newton tolerance (iteration cap, or no descent left)
  int yielded_triangles = 0;      // plasticity: triangles whose rest shape flowed
  int untangled_vertices = 0;     // untangling: cloth vertices moved out of colliders or back
                                  // through cloth before the step (collision.untangle)
  int tangled_crossings = 0;      // untangling: cloth edges still through cloth triangles after it
  double untangle_ms = 0.0;
  int thread_steps = 0;           // the threads each step ran on, summed (sim/thread_governor.hpp
                                  // may run fewer than settings.threads)
  EnergyFlows energy_flows;       // the step's energy budget (settings.energy_budget), J

  // Sums the counts and times of `step` into this (the residual keeps the largest).
  StepStats& operator+=(const StepStats& step);
};

class World {
 public:
  SolverSettings settings;

  void add_cloth(Cloth cloth, ContactMaterial material = {});
  // Throws std::invalid_argument for a mesh collider without triangles or with a broken one
  // (an index out of range, a triangle repeating a vertex).
  void add_collider(Collider collider);

  // Advances every cloth by settings.time_step.
  void step();

  double time() const { return time_; }
  // Live edits (the viewer's sliders, a checkpoint's restore) go through this, so it also drops
  // the potential each cloth's energy ledger carries to the next step (SolveLedger::carry_potential).
  std::vector<Cloth>& cloths();
  const std::vector<Cloth>& cloths() const { return cloths_; }
  const std::vector<Collider>& colliders() const { return colliders_; }
  std::vector<Collider>& colliders() { return colliders_; }  // live edits (friction) between steps
  // Friction and self-collision of cloth `cloth`; editable between steps like its thickness.
  ContactMaterial& contact_material(int cloth) { return materials_.at(static_cast<size_t>(cloth)); }
  const ContactMaterial& contact_material(int cloth) const {
    return materials_.at(static_cast<size_t>(cloth));
  }
  // External force on each vertex of cloth `cloth` (N, 3 x n_vertices, zero unless set), e.g. the
  // viewer's mouse spring. Held constant over a step and applied by every integrator as the
  // velocity impulse h f / m before it runs (exact for symplectic and implicit Euler).
  Positions& external_force(int cloth) { return external_forces_.at(static_cast<size_t>(cloth)); }
  // The collision phase's last proximity pairs (the contact penalty's input), for checkpoints;
  // a restored list takes effect at the next step.
  std::vector<std::array<int, 3>> contact_history() const { return collisions_.near_pairs(); }
  void restore_contact_history(std::vector<std::array<int, 3>> pairs) {
    restored_near_pairs_ = std::move(pairs);
    near_pairs_restored_ = true;
  }
  const StepStats& last_step_stats() const { return stats_; }
  // The last step's Newton iterations, one row each (every sub-step and cloth), when
  // settings.implicit.record_iterations is on (weft --newton-log); empty otherwise.
  struct NewtonLogRow {
    int substep;
    int cloth;
    int iteration;  // 0: the step's start
    NewtonIterationRecord record;
  };
  const std::vector<NewtonLogRow>& newton_log() const { return newton_log_; }
  // Contacts the collision response acted on in the last step (every sub-step).
  const std::vector<ContactRecord>& contacts() const { return collisions_.records(); }
  // The triangle mesh standing for collider k in the collision pipeline, posed at time().
  const TriangleMesh& collider_surface(int collider) const { return collider_surfaces_[collider]; }
  Positions collider_positions(int collider) const;
  Energies energies() const;

  // A view's copy of what `other`, a world with the same cloths and colliders, shows after its
  // last step: each cloth's positions and velocities (and rest shapes where plastic), the time, the step's
  // stats and contacts. This world's settings, materials and solver state stay as they are. Throws
  // std::logic_error when the cloths differ in number or size.
  void show_state_of(const World& other);

  // Checkpoints (io/checkpoint.hpp) save and restore what the step carries from one call to
  // the next beyond each cloth's state: the time, the colliders and the adaptive controller.
  void set_time(double time) { time_ = time; }
  AdaptiveState& adaptive_state(int cloth) { return solvers_[cloth]->adaptive; }
  const AdaptiveState& adaptive_state(int cloth) const { return solvers_[cloth]->adaptive; }

 private:
  // Per-cloth integrator storage, allocated on first use of each integrator.
  struct ClothSolvers {
    ImplicitEulerSolver implicit;
    XpbdSolver xpbd;
    ContactPenalty penalty;  // implicit Euler: the last step's contacts (collision.penalty_stiffness)
    ExplicitWorkspace explicit_workspace;
    AdaptiveState adaptive;
    ClothState trial;
    SolveLedger ledger;                  // settings.energy_budget: the solve phase's flows
    Eigen::VectorXd shortest_rest_edge;  // per vertex (settings.max_travel_edges), sized on first use
  };

  // settings.substeps, or the fewest sub-steps that keep every cloth vertex within
  // settings.max_travel_edges of its shortest rest edges (see there).
  // Whether contact runs inside the solve (collision.response "barrier" with implicit Euler).
  bool barrier_response() const;
  void untangle(StepStats& stats);
  void push_out_of_colliders(Positions& displacement, int& moved);
  int substeps_for_step();
  void prepare_barrier();
  void prepare_collisions(double h);
  void integrate(double h, int substep, StepStats& stats);
  void resolve_collisions(double h, StepStats& stats);
  int update_rest_state(EnergyFlows& flows);
  EnergyIdentity energy_identity() const;
  void integrate_cloth(int index, double h, int substep, StepStats& stats);

  std::vector<Cloth> cloths_;
  std::vector<std::unique_ptr<ClothSolvers>> solvers_;  // Eigen solvers do not move: held by pointer
  std::vector<Collider> colliders_;
  std::vector<TriangleMesh> collider_surfaces_;  // at time 0
  std::vector<ContactMaterial> materials_;       // per cloth
  CollisionPhase collisions_;
  BarrierContact barrier_;  // the barrier response's meshes and pairs
  bool barrier_meshes_stale_ = true;
  std::vector<Positions> step_start_;  // each cloth's positions at the sub-step's start
  std::vector<const Positions*> barrier_current_, barrier_start_;  // prepare_cloth's arguments
  std::vector<std::array<int, 3>> restored_near_pairs_;  // restore_contact_history, until the next step
  bool near_pairs_restored_ = false;
  bool collision_meshes_stale_ = true;      // cloths or colliders added since the last step
  // Untangling (collision.untangle): due at the first step and after a step that did not end
  // clean; the combined cloth mesh, and which colliders hold which cloths (a cloth that starts
  // mostly inside a solid, as in a drum, is not pushed out of it).
  Untangler untangler_;
  bool untangle_due_ = true;
  bool untangle_mesh_stale_ = true;
  std::vector<std::vector<char>> held_;   // per cloth, per collider
  Positions untangle_x_, untangle_push_;  // (3 x n_cloth_vertices), cloths in order
  Positions untangle_surface_;            // a collider's triangles' corners at the step's time
  Eigen::VectorXd untangle_inverse_mass_, untangle_margin_;
  std::vector<Positions> external_forces_;  // one per cloth (3 x n_vertices)
  double time_ = 0.0;
  StepStats stats_;
  std::vector<NewtonLogRow> newton_log_;  // newton_log(); allocates only to grow
  ThreadGovernor thread_governor_;
};

// Most integration sub-steps (steps x substeps) one frame may take. Even a 2x2 cloth needs
// about a microsecond per sub-step, so past this a frame takes seconds and a run hours; far past
// it the step count no longer fits an int. Scenes asking for more are refused (docs/scenes.md).
constexpr int max_steps_per_frame = 1'000'000;

// Most sub-steps settings.max_travel_edges cuts one step into: a velocity that would need more is
// a diverged cloth, which the stability checks report.
constexpr int max_travel_substeps = 64;

// Most solver threads: well above the cores of one node, and below the counts (thousands) at
// which libgomp hangs or crashes creating them.
constexpr int max_threads = 256;

// How a frame of 1/fps seconds is cut into equal steps no longer than max_time_step.
struct FrameSchedule {
  int steps_per_frame = 1;
  double time_step = 0.0;  // (1/fps) / steps_per_frame
};
// Throws std::out_of_range when that takes more than max_steps_per_frame steps.
FrameSchedule frame_schedule(double fps, double max_time_step);

// The steps frame_schedule would cut a frame into, as a double (no overflow; inf for h = 0).
double steps_per_frame(double fps, double max_time_step);

}  // namespace weft
