#pragma once
// The collision phase of a World step (docs/architecture.md, step 3; after Bridson, Fedkiw &
// Anderson 2002): every cloth, soft body and collider surface is laid out in one combined vertex,
// triangle and edge index space, and the integrator's candidate motion x_start -> x_end is
// corrected in place by these phases, each a member function the World calls in order:
//   gather_motion           combined x_start, x_end, velocity and inverse mass
//   find_candidates         broad phase: BVHs over triangles, vertices and edges refitted with
//                           swept boxes (rebuilt when loose), then self, cloth-cloth and
//                           cloth-collider vertex-face and edge-edge pairs queried directly
//   apply_proximity         narrow phase (pairs closer than the thickness at the start) and the
//                           repulsion + Coulomb friction impulses, per material pair
//   limit_strain            edges stretched past collision.strain_limit shortened (when on);
//                           again after each round's impulses, so the zones see the limited motion
//   apply_ccd_impulses      continuous detection over the step and inelastic impulses, iterated
//   apply_impact_zones      rigid impact zones, the fail-safe
//   verify_motion           the broad phase again on the corrected motion; collisions it finds
//                           (pairs that left their swept boxes) go round again
//   check_immovable_pairs   pairs of infinite-mass vertices only (left out of the response,
//                           which cannot move them) tested over the final motion
//   count_edges_over_limit  cloth edges the final motion leaves over collision.strain_limit
//   measure_corrections     how far the phase moved the cloth vertices from the integrator's
//                           end positions (the solve's work that the response undid or redid)
//   scatter_motion          the corrected positions and velocities back into the cloths
// Colliders are triangle meshes of infinite mass; kinematic ones move from their pose at t to
// their pose at t + h over the step.
#include <array>
#include <vector>

#include "collision/bvh.hpp"
#include "collision/candidates.hpp"
#include "collision/ccd_response.hpp"
#include "collision/collider.hpp"
#include "collision/collision_step.hpp"
#include "collision/contact_record.hpp"
#include "collision/impact_zones.hpp"
#include "collision/primitive_queries.hpp"
#include "collision/self_culling.hpp"
#include "collision/strain_limiting.hpp"
#include "core/topology.hpp"
#include "physics/cloth.hpp"
#include "physics/contact_penalty.hpp"
#include "sim/barrier_contact.hpp"

namespace weft {

// How a cloth meets others: Coulomb coefficients (a cloth-cloth pair uses the mean of the two
// cloths') and whether it is tested against itself.
struct ContactMaterial {
  double static_friction = 0.4;
  double kinetic_friction = 0.3;
  bool self_collision = true;
};

// How contact is handled: "impulse", the collision phase after the solve (this file), or
// "barrier", contact inside implicit Euler's solve (sim/barrier_contact.hpp), where that phase
// does not run.
enum class CollisionResponse { impulse, barrier };

struct CollisionSettings {
  bool enabled = true;
  CollisionResponse response = CollisionResponse::impulse;
  BarrierSettings barrier;               // the barrier response's settings
  double repulsion_stiffness = 1000.0;   // N/m, spring of the proximity repulsion
  double ccd_tolerance = 1e-6;           // m, eta of the continuous tests
  double ccd_separation = 0.1;           // fraction of the thickness a CCD impulse restores
  int max_ccd_passes = 8;                // CCD impulse passes before impact zones
  int max_impact_zone_passes = 64;       // zone passes before the involved vertices stop
  int max_rounds = 16;                   // CCD + zones rounds while verify_motion finds collisions
  double max_step_displacement = 100.0;  // m; a vertex moving farther in one step means divergence
  // N/m; > 0 adds the last step's proximity contacts to implicit Euler's incremental potential
  // as a one-sided quadratic penalty (physics/contact_penalty.hpp); 0: off
  double penalty_stiffness = 0.0;
  // > 0: implicit Euler's solve keeps each cloth vertex its thickness from the colliders it can
  // reach in the step (collider_contacts), a penalty of this many times the vertex's m / h^2; 0: off
  double collider_contact_ratio = 0.0;
  // > 0: after the proximity impulses and after each round's CCD impulses, cloth edges longer
  // than (1 + strain_limit) times their rest length are shortened to it
  // (collision/strain_limiting.hpp), in at most strain_limit_sweeps Gauss-Seidel sweeps; 0: off
  double strain_limit = 0.0;
  int strain_limit_sweeps = 32;
  BvhSettings bvh;
  // Skip self tests in flat, unfolded regions that cannot touch themselves (docs/collision.md,
  // "Self-collision culling"). Off by default; scenes turn it on where it pays.
  SelfCullingSettings self_culling = {false};
  // Before a step, after the first and after any that did not end clean: cloth inside colliders
  // and cloth through cloth moved back to its side (collision/untangling.hpp,
  // collision/collider_push_out.hpp); either response
  bool untangle = true;
};

// What the phase did in the last step, summed over sub-steps by the World.
struct CollisionPhaseStats {
  double broad_ms = 0.0;     // BVH refit/rebuild, primitive pair queries
  double narrow_ms = 0.0;    // proximity and continuous tests
  double response_ms = 0.0;  // impulses, friction, impact zones
  int vertex_face_candidates = 0;
  int edge_edge_candidates = 0;
  int proximity_contacts = 0;
  int ccd_impulses = 0;
  int impact_zone_vertices = 0;
  int held_pins = 0;                // cloth pins the zones' last resort held at their start
  int immovable_collisions = 0;     // collisions between infinite-mass vertices only (check_immovable_pairs)
  int edges_over_strain_limit = 0;  // cloth edges left over the limit (count_edges_over_limit)
  int strain_limited_edges = 0;     // edge corrections by strain limiting, summed over its sweeps
  double largest_correction = 0.0;  // m: farthest a cloth vertex ended from the integrator's end
                                    // position, over the steps (measure_corrections)
  int corrected_vertices = 0;       // cloth vertices moved by more than 1% of their thickness, summed
  int bvh_rebuilds = 0;
  int rounds = 0;     // CCD + zone rounds run
  bool clean = true;  // the final motion had no collision among the last candidates (and no pin
                      // was held); edges over the strain limit are counted apart

  // Sums the counts and times of `other` into this (the largest correction keeps the larger; clean
  // only when both are).
  CollisionPhaseStats& operator+=(const CollisionPhaseStats& other);
};

// One collider as the phase sees it: its surface at time 0 and its motion.
struct ColliderSurface {
  Positions rest_positions;  // (3 x n_vertices), scene coordinates at time 0
  Triangles triangles;       // (3 x n_triangles)
  ColliderMotion motion;
  double static_friction = 0.3;
  double kinetic_friction = 0.3;
};

class CollisionPhase {
 public:
  CollisionSettings settings;

  // Registers the meshes; call again whenever cloths or colliders are added. Allocates.
  void set_meshes(const std::vector<Cloth>& cloths, const std::vector<ContactMaterial>& materials,
                  const std::vector<ColliderSurface>& colliders);

  // Takes edited contact parameters (thickness, friction, self-collision) of meshes already
  // registered; the viewer changes them between steps. Allocates nothing.
  void update_parameters(const std::vector<Cloth>& cloths, const std::vector<ContactMaterial>& materials,
                         const std::vector<Collider>& colliders);

  // Before the integrator moves anything: the step starts at the cloths' current positions and
  // the colliders' poses at time t.
  void begin_step(const std::vector<Cloth>& cloths, double t);

  void gather_motion(const std::vector<Cloth>& cloths, double t, double h);
  // False when the gathered motion is not finite or moves a vertex farther than
  // max_step_displacement in one step: a diverged integration, which no contact response can
  // mend (and whose huge boxes would make every pair a candidate); the World then skips the phase.
  bool motion_is_valid() const { return motion_valid_; }
  void find_candidates();
  void apply_proximity();
  void limit_strain();
  void apply_ccd_impulses();
  void apply_impact_zones();
  // Returns true when the corrected motion still collides (another round is due).
  bool verify_motion();
  // A kinematic collider driven through pinned cloth, or pinned cloth through pinned cloth, has
  // nothing of finite mass to move: such pairs are left out of every response, and this tests
  // them over the final motion so that the step is not reported clean when they collide.
  void check_immovable_pairs();
  // Counts the cloth edges longer than (1 + strain_limit) times their rest length (to the
  // limiter's slack of 1e-3) at the end of the step, when a limit is set: what the limiter and the
  // zones could not bring back (a zone whose pins move non-rigidly, impact_zones.hpp).
  void count_edges_over_limit();
  // Compares the corrected end positions with the integrator's (still in `cloths`): the largest
  // distance and the vertices moved by more than 1% of their cloth's thickness, into stats().
  // Where the solve does not see a contact the phase undoes part of its motion every step, and
  // the next solve starts that far from its answer (docs/collision.md, "Collider contacts inside
  // implicit Euler").
  void measure_corrections(const std::vector<Cloth>& cloths);
  void scatter_motion(std::vector<Cloth>& cloths) const;

  // After begin_step, for implicit Euler's contact penalty: the pairs the last step's proximity
  // phase acted on that are still within twice their thickness, with closest points and normals
  // at the cloths' current positions, as contacts of cloth `cloth` (vertices of other meshes
  // folded into the offset), with `stiffness` (N/m). Appends to penalty.contacts; allocates only
  // to grow it.
  void penalty_contacts(int cloth, double stiffness, ContactPenalty& penalty);

  // After begin_step, for implicit Euler: each free vertex of cloth `cloth` that can come within
  // its thickness of a collider during the step (its start position swept by h |v| + h^2 |gravity|,
  // twice over, plus the thickness) gets one contact with the collider triangle nearest it (the
  // collider at t + h), a plane through that triangle's closest point with the normal towards the
  // vertex: the solve keeps the vertex at least its thickness from the plane, or as far as it
  // starts when nearer, with stiffness `ratio` times the vertex's m / h^2. Triangles are found in
  // the colliders' hierarchies as the last step left them (built here, swept over this step, when
  // none is yet), so a collider moving faster than the thickness a step can slip past one; the
  // collision phase after the solve still catches it.
  // Appends to penalty.contacts; allocates only to grow it.
  void collider_contacts(int cloth, const Cloth& state, double h, const Vec3& gravity, double ratio,
                         ContactPenalty& penalty);

  // The last step's proximity pairs (what penalty_contacts reads), for checkpoints: {0, vertex,
  // triangle} for vertex-face, {1, edge_a, edge_b} for edge-edge, in combined indices. Setting
  // them needs set_meshes first; pairs out of range are dropped.
  std::vector<std::array<int, 3>> near_pairs() const;
  void set_near_pairs(const std::vector<std::array<int, 3>>& pairs);

  const CollisionPhaseStats& stats() const { return stats_; }
  void reset_stats() {
    stats_ = {};
    records_.clear();
  }
  // Contacts acted on in the current step (positions at the start of the step).
  const std::vector<ContactRecord>& records() const { return records_; }
  // A view's copy of another phase's contacts (World::show_state_of).
  void show_records(const std::vector<ContactRecord>& records) { records_ = records; }

  int num_cloths() const { return num_cloths_; }

 private:
  struct MeshSlot {
    MeshIndexOffsets offsets;
    int num_vertices = 0;
    Triangles local_triangles;   // (3 x n_triangles), vertex indices within the mesh
    Triangles global_triangles;  // the same in combined vertex indices (what the BVH reads)
    Triangles vertex_entries;    // point_entries of the vertices (what vertex_bvh reads)
    Triangles edge_entries;      // segment_entries of the edges (what edge_bvh reads)
    MeshTopology topology;
    Bvh bvh;                          // over the triangles
    Bvh vertex_bvh;                   // over the vertices
    Bvh edge_bvh;                     // over the edges
    SelfCulling culling;              // cloths with self-collision: regions that cannot touch themselves
    OwnedPrimitives owned;            // the culled self walk's owner of each vertex and edge
    std::vector<int> broken_regions;  // verify_motion: nodes culled before and not now
    bool built = false;
    bool moves = true;       // cloths, kinematic colliders
    double thickness = 0.0;  // cloths; 0 for colliders
    bool soft_body = false;
  };

  CollisionStep make_step();
  void refit_bounding_volumes();
  // One mesh's three hierarchies over boxes swept from `from` to `to`: built when not yet built or
  // too loose, else refitted.
  void update_bounding_volumes(MeshSlot& slot, const Positions& from, const Positions& to);
  PrimitiveMesh primitive_mesh(const MeshSlot& slot) const;
  void query_candidates(CollisionCandidates& candidates);
  void query_escaped_candidates(CollisionCandidates& candidates);
  void query_broken_regions(CollisionCandidates& candidates);
  // Moves pairs whose four vertices all have infinite mass (nothing can move them) out of
  // `candidates`, into `immovable` when given (check_immovable_pairs tests them).
  void drop_immovable_pairs(CollisionCandidates& candidates, CollisionCandidates* immovable) const;
  int material_group(int mesh_a, int mesh_b) const;
  int vertex_face_group(const VertexFacePair& pair) const;
  int edge_edge_group(const EdgeEdgePair& pair) const;
  // Contact distance of a pair: the larger thickness of the two meshes.
  double pair_thickness(int vertex_a, int vertex_b) const;
  ResponseSettings response_settings(int group) const;
  ResponseSettings ccd_settings() const;
  double box_margin() const { return 0.5 * max_thickness_; }
  void label_records(size_t first);
  // The candidates with a vertex flagged in `flags` (per vertex), in candidate order, into `out`.
  void list_pairs_touching(const std::vector<char>& flags, CollisionCandidates& out) const;

  std::vector<MeshSlot> meshes_;            // cloths first, then colliders
  std::vector<ContactMaterial> materials_;  // per cloth
  std::vector<ColliderSurface> colliders_;
  int num_cloths_ = 0;
  double max_thickness_ = 0.0;
  double time_step_ = 0.0;
  bool motion_valid_ = true;

  // Combined state of the step.
  Positions x_start_;   // (3 x n_vertices)
  Positions x_end_;     // (3 x n_vertices)
  Positions velocity_;  // (3 x n_vertices)
  // (3 x n_vertices) corners of each vertex's box swept over the step, which the candidates were
  // found for; verify_motion grows the boxes of vertices whose corrected motion left them
  Positions vertex_lower_;
  Positions vertex_upper_;
  Eigen::VectorXd inverse_mass_;          // (n_vertices)
  Triangles triangles_;                   // (3 x n_triangles)
  Eigen::Matrix2Xi edges_;                // (2 x n_edges)
  std::vector<double> edge_rest_length_;  // (n_edges) cloth edges at rest; 0 for collider edges
  std::vector<int> vertex_mesh_;          // mesh of each combined vertex (n_vertices)
  std::vector<char> holdable_;            // 1 for cloth vertices (CollisionStep::holdable), 0 for colliders

  // Scratch kept between steps.
  BvhQueryBuffers buffers_;
  CollisionCandidates candidates_;
  CollisionCandidates verify_candidates_;
  CollisionCandidates retested_;    // apply_ccd_impulses: the pairs a pass after the first tests
  std::vector<char> retest_flags_;  // per vertex: list_pairs_touching's flags (a vertex to test again)
  // apply_ccd_impulses: the motion its passes left clean (when they did), for apply_impact_zones
  // to test again only the pairs with a vertex moved since (zone_first_pairs_).
  Positions clean_x_end_;
  bool clean_snapshot_ = false;
  CollisionCandidates zone_first_pairs_;
  CollisionCandidates region_candidates_, region_immovable_;  // query_broken_regions' lists
  CollisionCandidates immovable_candidates_;  // the pairs drop_immovable_pairs took out of query_candidates's
  std::vector<char> culled_before_;           // verify_motion: the culling the candidates were found with
  std::vector<int> escaped_vertices_;         // verify_motion: vertices whose corrected motion left their box
  std::vector<char> escaped_flags_;           // per vertex
  MovedPrimitives escaped_primitives_;        // of one cloth, touching escaped vertices
  std::vector<std::vector<int>> box_triangles_;    // append_moved_primitive_candidates' scratch, one a thread
  std::vector<std::vector<int>> reach_triangles_;  // collider_contacts' scratch, one a thread
  std::vector<PenaltyContact> reach_slots_;        // collider_contacts: a vertex's contact with each collider
  std::vector<char> reach_found_;                  // ... and whether it has one
  Positions reach_positions_;                      // collider_contacts: the colliders' columns, at t + h
  double step_start_time_ = 0.0;                   // begin_step's t
  GroupedPairs<VertexFacePair> near_vertex_faces_;  // the last proximity phase's pairs by material group
  GroupedPairs<EdgeEdgePair> near_edge_edges_;
  std::vector<char> near_vertex_face_;
  std::vector<char> near_edge_edge_;
  CcdCollisions collisions_;
  ImpactZoneWorkspace zone_workspace_;
  std::vector<ContactRecord> records_;
  CollisionPhaseStats stats_;
};

}  // namespace weft
