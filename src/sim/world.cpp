#include "sim/world.hpp"

#include <array>

#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "collision/collider_geometry.hpp"
#include "collision/collider_push_out.hpp"
#include "core/phase_timer.hpp"
#include "core/topology.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/symplectic_euler.hpp"

namespace weft {

namespace {

// The largest over the triangles of the radius of the smallest circle holding the triangle: half
// the longest edge where the angle facing it is right or obtuse, else the circumradius
// |a||b||a - b| / (2 |a x b|) (a, b the edges from one corner).
double largest_enclosing_radius(const Triangles& triangles, const Positions& x) {
  double largest = 0.0;
  for (int t = 0; t < triangles.cols(); ++t) {
    const Vec3 p = x.col(triangles(0, t));
    const Vec3 a = x.col(triangles(1, t)) - p, b = x.col(triangles(2, t)) - p;
    std::array<double, 3> squared = {a.squaredNorm(), b.squaredNorm(), (a - b).squaredNorm()};
    std::sort(squared.begin(), squared.end());
    const double radius = squared[2] >= squared[0] + squared[1]
                              ? 0.5 * std::sqrt(squared[2])
                              : std::sqrt(squared[0] * squared[1] * squared[2]) / (2.0 * a.cross(b).norm());
    largest = std::max(largest, radius);
  }
  return largest;
}

}  // namespace

void World::add_cloth(Cloth cloth, ContactMaterial material) {
  external_forces_.push_back(Positions::Zero(3, cloth.num_vertices()));
  cloths_.push_back(std::move(cloth));
  solvers_.push_back(std::make_unique<ClothSolvers>());
  materials_.push_back(material);
  collision_meshes_stale_ = true;
  barrier_meshes_stale_ = true;
  untangle_mesh_stale_ = true;
  untangle_due_ = true;
}

void World::add_collider(Collider collider) {
  TriangleMesh surface = weft::collider_surface(collider);
  build_topology(surface.triangles,
                 surface.num_vertices());  // throws on a broken mesh, here and not mid-step
  collider_surfaces_.push_back(std::move(surface));
  colliders_.push_back(std::move(collider));
  collision_meshes_stale_ = true;
  barrier_meshes_stale_ = true;
  untangle_mesh_stale_ = true;
  untangle_due_ = true;
}

std::vector<Cloth>& World::cloths() {
  for (const std::unique_ptr<ClothSolvers>& solvers : solvers_) solvers->ledger.forget_carried_potential();
  return cloths_;
}

void World::show_state_of(const World& other) {
  if (other.cloths_.size() != cloths_.size()) throw std::logic_error("World::show_state_of: other cloths");
  for (size_t c = 0; c < cloths_.size(); ++c) {
    if (other.cloths_[c].num_vertices() != cloths_[c].num_vertices())
      throw std::logic_error("World::show_state_of: another cloth size");
    cloths_[c].state.x = other.cloths_[c].state.x;
    cloths_[c].state.v = other.cloths_[c].state.v;
    // Plastic flow moves the rest shapes, which the strain map reads.
    if (other.cloths_[c].model.membrane.plastic())
      cloths_[c].model.membrane.rest = other.cloths_[c].model.membrane.rest;
  }
  time_ = other.time_;
  stats_ = other.stats_;
  collisions_.show_records(other.collisions_.records());
}

Positions World::collider_positions(int collider) const {
  const Positions& rest = collider_surfaces_[collider].positions;
  Positions positions(3, rest.cols());
  colliders_[collider].motion.place(rest, time_, positions);
  return positions;
}

// One time step, as the pipeline in docs/architecture.md: colliders, integrator, collisions,
// rest state, stats.
void World::step() {
  const auto step_start = PhaseClock::now();
  StepStats stats;
  newton_log_.clear();
  // Threads for our loops and for Eigen's sparse products (row-parallel, so results do not
  // depend on the count).
  thread_governor_.set_requested(settings.threads);
  const int threads = settings.adapt_threads ? thread_governor_.threads() : std::max(1, settings.threads);
  omp_set_num_threads(threads);
  Eigen::setNbThreads(threads);
  const int substeps = substeps_for_step();
  const double h = settings.time_step / substeps;
  collisions_.reset_stats();
  const bool barrier = barrier_response();
  {
    PhaseTimer timer(stats.untangle_ms);
    untangle(stats);
  }
  for (int substep = 0; substep < substeps; ++substep) {
    {
      PhaseTimer timer(stats.prepare_collisions_ms);
      if (barrier) {
        prepare_barrier();
      } else {
        prepare_collisions(h);
      }
    }
    {
      PhaseTimer timer(stats.integrate_ms);
      integrate(h, substep, stats);
    }
    {
      PhaseTimer timer(stats.collisions_ms);
      if (!barrier) resolve_collisions(h, stats);
    }
    time_ += h;
    {
      PhaseTimer timer(stats.rest_update_ms);
      stats.yielded_triangles += update_rest_state(stats.energy_flows);
    }
  }
  if (!stats.collision.clean) untangle_due_ = true;  // the step may have left cloth through cloth
  stats.total_ms = milliseconds_since(step_start);
  stats.steps = 1;
  stats.substeps = substeps;
  stats.thread_steps = threads;
  stats_ = stats;
  if (settings.adapt_threads) thread_governor_.record(1e-3 * stats.total_ms);
}

// Untangling (collision/untangling.hpp, collision/collider_push_out.hpp), before the step: cloth
// vertices inside a collider are moved out of it, then passes of the cloth-cloth analysis move the
// sides that passed through cloth back, until no cloth edge pierces a cloth triangle or a pass
// moves nothing. It runs at the first step and after a step that did not end clean, the only
// steps after which cloth can be inside cloth or a collider; a clean state costs one check.
// The energy it adds or removes is booked as contact.
void World::untangle(StepStats& stats) {
  if (!untangle_due_ || !settings.collision.enabled || !settings.collision.untangle || cloths_.empty())
    return;
  untangle_due_ = false;
  int num_vertices = 0;
  for (const Cloth& cloth : cloths_) num_vertices += cloth.num_vertices();
  if (untangle_mesh_stale_) {
    int num_triangles = 0;
    for (const Cloth& cloth : cloths_) num_triangles += static_cast<int>(cloth.model.triangles.cols());
    Triangles triangles(3, num_triangles);
    std::vector<int> vertex_mesh;
    vertex_mesh.reserve(static_cast<size_t>(num_vertices));
    int vertex_offset = 0;
    int triangle_offset = 0;
    for (size_t c = 0; c < cloths_.size(); ++c) {
      const Triangles& local = cloths_[c].model.triangles;
      triangles.middleCols(triangle_offset, local.cols()) = local.array() + vertex_offset;
      vertex_mesh.insert(vertex_mesh.end(), static_cast<size_t>(cloths_[c].num_vertices()),
                         static_cast<int>(c));
      vertex_offset += cloths_[c].num_vertices();
      triangle_offset += static_cast<int>(local.cols());
    }
    untangler_.set_mesh(triangles, vertex_mesh);
    held_.clear();
    untangle_mesh_stale_ = false;
  }
  untangle_x_.resize(3, num_vertices);
  untangle_inverse_mass_.resize(num_vertices);
  untangle_margin_.resize(num_vertices);
  int offset = 0;
  for (const Cloth& cloth : cloths_) {
    const int n = cloth.num_vertices();
    untangle_x_.middleCols(offset, n) = cloth.state.x;
    untangle_inverse_mass_.segment(offset, n) = cloth.model.inverse_mass;
    untangle_margin_.segment(offset, n).setConstant(cloth.model.thickness);
    offset += n;
  }

  int moved = 0;
  untangle_push_.setZero(3, num_vertices);
  push_out_of_colliders(untangle_push_, moved);
  if (moved > 0) untangle_x_ += untangle_push_;
  constexpr int max_passes = 8;
  int crossings = 0;
  for (int pass = 0; pass < max_passes; ++pass) {
    crossings = static_cast<int>(untangler_.find_crossings(untangle_x_).size());
    if (crossings == 0) break;
    const UntanglePass result =
        untangler_.plan_pushes(untangle_x_, untangle_inverse_mass_, untangle_margin_, untangle_push_);
    if (result.moved_vertices == 0) break;
    untangle_x_ += untangle_push_;
    moved += result.moved_vertices;
    if (pass + 1 == max_passes) crossings = static_cast<int>(untangler_.find_crossings(untangle_x_).size());
  }
  stats.tangled_crossings = crossings;
  stats.untangled_vertices = moved;
  // Checked again at the next step, until a check moves nothing and finds nothing.
  untangle_due_ = crossings > 0 || moved > 0;
  if (moved == 0) return;

  double energy_before = 0.0;
  if (settings.energy_budget) {
    for (const Cloth& cloth : cloths_)
      energy_before += kinetic_energy(cloth) + potential_energy(cloth, settings.gravity);
  }
  offset = 0;
  for (size_t c = 0; c < cloths_.size(); ++c) {
    const int n = cloths_[c].num_vertices();
    cloths_[c].state.x = untangle_x_.middleCols(offset, n);
    solvers_[c]->ledger.forget_carried_potential();
    offset += n;
  }
  if (settings.energy_budget) {
    double energy_after = 0.0;
    for (const Cloth& cloth : cloths_)
      energy_after += kinetic_energy(cloth) + potential_energy(cloth, settings.gravity);
    stats.energy_flows.contact += energy_before - energy_after;
  }
}

// The collider half of untangling: each cloth's free vertices inside a collider with an inside,
// unless the collider holds the cloth (decided at the first call: more than half of the cloth's
// vertices inside), moved out along the collider's normal. Adds to `displacement`.
void World::push_out_of_colliders(Positions& displacement, int& moved) {
  const bool decide = held_.empty();
  if (decide) held_.assign(cloths_.size(), std::vector<char>(colliders_.size(), 0));
  for (size_t k = 0; k < colliders_.size(); ++k) {
    const Collider& collider = colliders_[k];
    if (!collider_has_inside(collider)) continue;
    untangle_surface_.resize(3, collider_surfaces_[k].positions.cols());
    collider.motion.place(collider_surfaces_[k].positions, time_, untangle_surface_);
    int offset = 0;
    for (size_t c = 0; c < cloths_.size(); ++c) {
      const Cloth& cloth = cloths_[c];
      const int n = cloth.num_vertices();
      if (decide) {
        int inside = 0;
        for (int v = 0; v < n; ++v) inside += signed_distance_at(collider, cloth.state.x.col(v), time_) < 0.0;
        held_[c][k] = 2 * inside > n;
      }
      if (!held_[c][k]) {
        moved += push_out_of_collider(collider, time_, untangle_surface_, collider_surfaces_[k].triangles,
                                      untangle_x_.middleCols(offset, n), cloth.model.triangles,
                                      cloth.model.inverse_mass, cloth.model.thickness,
                                      displacement.middleCols(offset, n))
                     .moved;
      }
      offset += n;
    }
  }
}

// With n sub-steps a vertex travels (h/n) |v| + (h/n)^2 |g| <= (h |v| + h^2 |g|) / n, so n = the
// largest ratio of h |v| + h^2 |g| to max_travel_edges times the vertex's shortest rest edge,
// rounded up, keeps every vertex within the bound (velocities at the step's start).
int World::substeps_for_step() {
  const int requested = std::max(1, settings.substeps);
  if (!(settings.max_travel_edges > 0.0)) return requested;
  const double h = settings.time_step;
  const double fall = h * h * settings.gravity.norm();
  double ratio = 0.0;
  for (size_t c = 0; c < cloths_.size(); ++c) {
    const Cloth& cloth = cloths_[c];
    Eigen::VectorXd& shortest = solvers_[c]->shortest_rest_edge;
    const Positions& rest = cloth.model.rest_positions;
    if (shortest.size() != rest.cols()) {
      shortest.setConstant(rest.cols(), std::numeric_limits<double>::infinity());
      const Triangles& triangles = cloth.model.triangles;
      for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
        for (int k = 0; k < 3; ++k) {
          const int a = triangles(k, t), b = triangles((k + 1) % 3, t);
          const double length = (rest.col(a) - rest.col(b)).norm();
          shortest[a] = std::min(shortest[a], length);
          shortest[b] = std::min(shortest[b], length);
        }
      }
    }
    for (Eigen::Index i = 0; i < rest.cols(); ++i) {
      if (!(shortest[i] > 0.0) || !std::isfinite(shortest[i])) continue;  // on no triangle, or degenerate
      const double travel = h * cloth.state.v.col(i).norm() + fall;
      ratio = std::max(ratio, travel / (settings.max_travel_edges * shortest[i]));
    }
  }
  // NaN velocities compare false: left to the stability checks at the requested count.
  if (!(ratio > requested)) return requested;
  return static_cast<int>(std::min<double>(max_travel_substeps, std::ceil(ratio)));
}

bool World::barrier_response() const {
  return settings.collision.enabled && settings.collision.response == CollisionResponse::barrier &&
         settings.integrator == IntegratorKind::implicit_euler && !cloths_.empty();
}

// The barrier response's meshes (registered once: its colliders are static) and each cloth's
// positions at the sub-step's start (the others' friction displacement in a cloth's solve).
void World::prepare_barrier() {
  barrier_.settings = settings.collision.barrier;
  if (barrier_meshes_stale_) {
    std::vector<BarrierMesh> meshes;
    for (size_t c = 0; c < cloths_.size(); ++c) {
      const Cloth& cloth = cloths_[c];
      meshes.push_back({cloth.model.triangles, cloth.state.x, cloth.model.thickness,
                        materials_[c].kinetic_friction, materials_[c].self_collision, true});
    }
    std::vector<Collider> analytic;
    std::vector<BarrierBall> balls;
    // Room for every cloth triangle's enclosing radius to grow by half (the balls' vertex radius).
    double rho = 0.0;
    for (const Cloth& cloth : cloths_)
      rho = std::max(rho, largest_enclosing_radius(cloth.model.triangles, cloth.state.x));
    rho *= 1.5;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      // An analytic sphere is a ball (sim/barrier_contact.hpp) unless a cloth vertex starts within
      // its vertex radius (a cloth held inside, or laid on it): its mesh's pairs then hold from there.
      if (settings.collision.barrier.analytic_colliders && colliders_[k].shape == ColliderShape::sphere) {
        const Vec3 center = colliders_[k].center;
        const double radius =
            (collider_positions(static_cast<int>(k)).colwise() - center).colwise().norm().maxCoeff();
        const double vertex_radius = std::sqrt(radius * radius + rho * rho);
        bool near = false;
        for (const Cloth& cloth : cloths_) {
          near = near || ((cloth.state.x.colwise() - center).colwise().norm().array() < vertex_radius).any();
        }
        if (!near) {
          balls.push_back({center, radius, vertex_radius, colliders_[k].friction});
          continue;
        }
      }
      if (settings.collision.barrier.analytic_colliders && colliders_[k].shape != ColliderShape::mesh) {
        analytic.push_back(colliders_[k]);
        continue;
      }
      meshes.push_back({collider_surfaces_[k].triangles, collider_positions(static_cast<int>(k)), 0.0,
                        colliders_[k].friction, false, false});
    }
    barrier_.set_meshes(meshes, analytic, balls);
    barrier_meshes_stale_ = false;
  }
  step_start_.resize(cloths_.size());
  barrier_current_.clear();
  barrier_start_.clear();
  for (size_t c = 0; c < cloths_.size(); ++c) {
    step_start_[c] = cloths_[c].state.x;
    barrier_current_.push_back(&cloths_[c].state.x);
    barrier_start_.push_back(&step_start_[c]);
  }
}

// Kinematic colliders follow their scripted motion: the collision phase poses them at both ends
// of the step (t and t + h), and the step starts from the cloths' current positions.
void World::prepare_collisions(double /*h*/) {
  if (collision_meshes_stale_) {
    std::vector<ColliderSurface> surfaces;
    for (size_t k = 0; k < colliders_.size(); ++k) {
      const Collider& collider = colliders_[k];
      surfaces.push_back({collider_surfaces_[k].positions, collider_surfaces_[k].triangles, collider.motion,
                          collider.static_friction, collider.friction});
    }
    collisions_.set_meshes(cloths_, materials_, surfaces);
    collision_meshes_stale_ = false;
  }
  collisions_.update_parameters(cloths_, materials_, colliders_);
  if (near_pairs_restored_) {
    collisions_.set_near_pairs(restored_near_pairs_);
    near_pairs_restored_ = false;
  }
  collisions_.begin_step(cloths_, time_);
}

void World::integrate(double h, int substep, StepStats& stats) {
  for (size_t c = 0; c < cloths_.size(); ++c) {
    Cloth& cloth = cloths_[c];
    ClothSolvers& solvers = *solvers_[c];
    // External forces (the viewer's mouse spring) enter as an impulse v += h M^-1 f; pinned
    // vertices have inverse mass 0.
    const Positions& external_force = external_forces_[c];
    const bool budget = settings.energy_budget;
    const double kinetic_before = budget ? kinetic_energy(cloth) : 0.0;
    if (!external_force.isZero(0.0)) {
      cloth.state.v.noalias() += h * (external_force * cloth.model.inverse_mass.asDiagonal());
    }
    // Scripted pins get the velocity that lands them on their target at t + h; the integrators
    // never move a pinned vertex otherwise, and placing them afterwards removes round-off.
    const bool scripted = !cloth.model.scripted_pins.empty();
    if (scripted) drive_scripted_pins(cloth.model.scripted_pins, time_, h, cloth.state.x, cloth.state.v);
    if (budget) {
      stats.energy_flows.external_work += kinetic_energy(cloth) - kinetic_before;
      solvers.ledger.begin(cloth, settings.gravity, energy_identity() == EnergyIdentity::symplectic_euler);
    } else {
      solvers.ledger.forget_carried_potential();  // the cloth moves on unmeasured
    }
    solvers.penalty.contacts.clear();
    if (barrier_response()) {
      barrier_.prepare_cloth(static_cast<int>(c), barrier_current_, barrier_start_, cloth.model.inverse_mass,
                             cloth.model.mass.sum() / std::max<Eigen::Index>(1, cloth.model.mass.size()));
    } else if (settings.collision.enabled && settings.integrator == IntegratorKind::implicit_euler) {
      if (settings.collision.penalty_stiffness > 0.0) {
        collisions_.penalty_contacts(static_cast<int>(c), settings.collision.penalty_stiffness,
                                     solvers.penalty);
      }
      if (settings.collision.collider_contact_ratio > 0.0) {
        collisions_.collider_contacts(static_cast<int>(c), cloth, h, settings.gravity,
                                      settings.collision.collider_contact_ratio, solvers.penalty);
      }
      solvers.penalty.index_vertices(static_cast<int>(cloth.state.x.cols()));
    }
    integrate_cloth(static_cast<int>(c), h, substep, stats);
    if (scripted) place_scripted_pins(cloth.model.scripted_pins, time_ + h, cloth.state.x);
    if (budget) {
      switch (energy_identity()) {
        case EnergyIdentity::implicit_euler:
          stats.energy_flows +=
              solvers.ledger.implicit_euler(cloth, settings.gravity, h, &solvers.penalty,
                                            solvers.implicit.last_evaluation_at(cloth.state.x));
          break;
        case EnergyIdentity::symplectic_euler:
          stats.energy_flows += solvers.ledger.symplectic_euler(cloth, settings.gravity);
          break;
        case EnergyIdentity::none:
          stats.energy_flows += solvers.ledger.whole_change(cloth, settings.gravity);
          break;
      }
    }
  }
}

// The energy identity the ledger applies (energy_ledger.hpp): implicit Euler, symplectic Euler
// taking one step, or none (any other integrator, adaptive sub-steps).
EnergyIdentity World::energy_identity() const {
  if (settings.integrator == IntegratorKind::implicit_euler) return EnergyIdentity::implicit_euler;
  if (settings.integrator == IntegratorKind::symplectic_euler && !settings.adaptive.enabled) {
    return EnergyIdentity::symplectic_euler;
  }
  return EnergyIdentity::none;
}

void World::integrate_cloth(int index, double h, int substep, StepStats& stats) {
  Cloth& cloth = cloths_[index];
  ClothSolvers& solvers = *solvers_[index];
  const bool explicit_integrator = settings.integrator == IntegratorKind::symplectic_euler ||
                                   settings.integrator == IntegratorKind::midpoint_euler_cromer ||
                                   settings.integrator == IntegratorKind::explicit_midpoint;
  if (explicit_integrator && settings.adaptive.enabled) {
    const int accepted = solvers.adaptive.accepted, rejected = solvers.adaptive.rejected;
    const int unmet = solvers.adaptive.unmet;
    adaptive_advance(cloth, settings.integrator, settings.gravity, h, settings.adaptive, solvers.adaptive,
                     solvers.explicit_workspace, solvers.trial);
    stats.accepted_steps += solvers.adaptive.accepted - accepted;
    stats.rejected_steps += solvers.adaptive.rejected - rejected;
    stats.unmet_tolerance_steps += solvers.adaptive.unmet - unmet;
    return;
  }
  switch (settings.integrator) {
    case IntegratorKind::symplectic_euler:
      symplectic_euler_step(cloth, settings.gravity, h);
      break;
    case IntegratorKind::midpoint_euler_cromer:
      midpoint_euler_cromer_step(cloth, settings.gravity, h, solvers.explicit_workspace);
      break;
    case IntegratorKind::explicit_midpoint:
      explicit_midpoint_step(cloth, settings.gravity, h, solvers.explicit_workspace);
      break;
    case IntegratorKind::implicit_euler: {
      SolveContact* contact = barrier_response() ? &barrier_ : nullptr;
      const NewtonReport& report =
          solvers.implicit.step(cloth, settings.gravity, h, settings.implicit, &solvers.penalty, contact);
      if (contact != nullptr) {
        const SolveContactReport& found = contact->report();
        stats.contacts += found.pairs;
        stats.collision.proximity_contacts += found.pairs;
        stats.collision.vertex_face_candidates += found.vertex_face_candidates;
        stats.collision.edge_edge_candidates += found.edge_edge_candidates;
      }
      stats.newton_iterations += report.newton_iterations;
      stats.linear_iterations += report.linear_iterations;
      stats.residual = std::max(stats.residual, report.residual);
      stats.unconverged_steps += !report.converged;
      for (size_t k = 0; k < report.iterations.size(); ++k) {
        newton_log_.push_back({substep, index, static_cast<int>(k), report.iterations[k]});
      }
      break;
    }
    case IntegratorKind::xpbd:
      solvers.xpbd.step(cloth, settings.gravity, h, settings.xpbd);
      break;
  }
}

// Plastic flow: membrane rest shapes follow strains past the yield limit (docs/architecture.md,
// step 4).
// The elastic energy the flow releases is the plastic term of the energy budget.
int World::update_rest_state(EnergyFlows& flows) {
  int yielded = 0;
  for (size_t c = 0; c < cloths_.size(); ++c) {
    Cloth& cloth = cloths_[c];
    if (cloth.model.membrane.plastic()) {
      solvers_[c]->ledger.forget_carried_potential();  // rest shapes may flow: U changes
      const double before = settings.energy_budget ? potential_energy(cloth, settings.gravity) : 0.0;
      yielded += apply_membrane_plasticity(cloth.model.membrane, cloth.model.triangles, cloth.state.x);
      if (settings.energy_budget) flows.plastic += before - potential_energy(cloth, settings.gravity);
    }
  }
  return yielded;
}

// Collision response on the candidate motion (docs/architecture.md, step 3; collision_phase.hpp).
void World::resolve_collisions(double h, StepStats& stats) {
  if (!settings.collision.enabled || cloths_.empty()) return;
  CollisionPhase& phase = collisions_;
  phase.settings = settings.collision;
  // The penalty acts only inside implicit Euler; the friction bound must not count it otherwise.
  if (settings.integrator != IntegratorKind::implicit_euler) {
    phase.settings.penalty_stiffness = 0.0;
    phase.settings.collider_contact_ratio = 0.0;
  }
  phase.gather_motion(cloths_, time_, h);
  if (!phase.motion_is_valid()) {
    stats.collision.clean = false;  // diverged: left to the caller's divergence check
    return;
  }
  // The collision phase's change of energy is the contact term of the budget; the solve left
  // each cloth's potential in its ledger.
  double energy_before = 0.0;
  if (settings.energy_budget) {
    for (size_t c = 0; c < cloths_.size(); ++c) {
      energy_before += kinetic_energy(cloths_[c]) + solvers_[c]->ledger.end_potential();
    }
  }
  phase.find_candidates();
  phase.apply_proximity();
  phase.limit_strain();
  for (int round = 0; round < std::max(1, settings.collision.max_rounds); ++round) {
    phase.apply_ccd_impulses();
    phase.limit_strain();
    phase.apply_impact_zones();
    if (!phase.verify_motion()) break;
  }
  phase.check_immovable_pairs();
  phase.count_edges_over_limit();
  phase.measure_corrections(cloths_);
  phase.scatter_motion(cloths_);
  if (settings.energy_budget) {
    double energy_after = 0.0;
    for (size_t c = 0; c < cloths_.size(); ++c) {
      // A cloth the phase left where the solve ended has the solve's U (its last evaluation).
      const IncrementalPotentialParts* unmoved = solvers_[c]->implicit.last_evaluation_at(cloths_[c].state.x);
      const double potential =
          unmoved != nullptr ? unmoved->potential : potential_energy(cloths_[c], settings.gravity);
      energy_after += kinetic_energy(cloths_[c]) + potential;
      solvers_[c]->ledger.carry_potential(potential, settings.gravity);  // the next step starts here
    }
    stats.energy_flows.contact += energy_before - energy_after;
  }

  // The phase sums its stats over the sub-steps so far; the step keeps whether any was unclean.
  const bool clean_so_far = stats.collision.clean;
  stats.collision = phase.stats();
  stats.collision.clean = clean_so_far && phase.stats().clean;
  stats.contacts = stats.collision.proximity_contacts + stats.collision.ccd_impulses;
}

Energies World::energies() const {
  Energies energies;
  for (const Cloth& cloth : cloths_) {
    const ClothState& state = cloth.state;
    energies.kinetic += kinetic_energy(cloth);
    TermEnergies terms;
    evaluate_potential(cloth.model, settings.gravity, state.x, nullptr, nullptr, HessianStencils{}, false,
                       &terms);
    energies.gravitational += terms.gravity;
    energies.elastic += terms.elastic();
    energies.terms += terms;
  }
  return energies;
}

StepStats& StepStats::operator+=(const StepStats& step) {
  prepare_collisions_ms += step.prepare_collisions_ms;
  integrate_ms += step.integrate_ms;
  collisions_ms += step.collisions_ms;
  total_ms += step.total_ms;
  rest_update_ms += step.rest_update_ms;
  collision += step.collision;
  steps += step.steps;
  substeps += step.substeps;
  contacts += step.contacts;
  yielded_triangles += step.yielded_triangles;
  untangled_vertices += step.untangled_vertices;
  tangled_crossings = step.tangled_crossings;
  untangle_ms += step.untangle_ms;
  thread_steps += step.thread_steps;
  newton_iterations += step.newton_iterations;
  linear_iterations += step.linear_iterations;
  accepted_steps += step.accepted_steps;
  rejected_steps += step.rejected_steps;
  unmet_tolerance_steps += step.unmet_tolerance_steps;
  residual = std::max(residual, step.residual);
  unconverged_steps += step.unconverged_steps;
  energy_flows += step.energy_flows;
  return *this;
}

double steps_per_frame(double fps, double max_time_step) {
  // The small tolerance keeps an exact divisor (1/600 into 1/60) from rounding up to one more step.
  return std::max(1.0, std::ceil((1.0 / fps) / max_time_step - 1e-9));
}

FrameSchedule frame_schedule(double fps, double max_time_step) {
  // Checked before the cast: a tiny step (1e-12 s) would overflow the int and run at h = 1/fps.
  const double steps = steps_per_frame(fps, max_time_step);
  if (!(steps <= max_steps_per_frame)) {
    throw std::out_of_range("frame_schedule: a frame of 1/" + std::to_string(fps) +
                            " s in steps of at most " + std::to_string(max_time_step) +
                            " s needs more than " + std::to_string(max_steps_per_frame) + " steps");
  }
  FrameSchedule schedule;
  schedule.steps_per_frame = static_cast<int>(steps);
  schedule.time_step = (1.0 / fps) / schedule.steps_per_frame;
  return schedule;
}

}  // namespace weft
