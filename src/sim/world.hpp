#pragma once
// The World owns the cloths and colliders and advances them through the step pipeline
// (DESIGN.md, "One time step"). There is no global world: the caller owns each one.
#include <vector>

#include "collision/collider.hpp"
#include "physics/cloth.hpp"
#include "physics/integrator.hpp"

namespace weft {

struct SolverSettings {
  IntegratorKind integrator = IntegratorKind::symplectic_euler;
  double time_step = 1.0 / 600.0;  // s, h of one call to World::step()
  int substeps = 1;                // integration sub-steps of h / substeps inside one step
  Vec3 gravity{0.0, -9.81, 0.0};   // m/s^2
};

struct Energies {
  double kinetic = 0.0;
  double gravitational = 0.0;
  double elastic = 0.0;            // springs
  double total() const { return kinetic + gravitational + elastic; }
};

// Wall-clock milliseconds per phase of the last World::step(), and what it found.
struct StepStats {
  double move_colliders_ms = 0.0;
  double integrate_ms = 0.0;
  double collisions_ms = 0.0;
  double total_ms = 0.0;
  int contacts = 0;
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
  const StepStats& last_step_stats() const { return stats_; }
  Energies energies() const;

 private:
  void move_colliders(double h);
  void integrate(double h);
  int resolve_collisions(double h);

  std::vector<Cloth> cloths_;
  std::vector<Collider> colliders_;
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
