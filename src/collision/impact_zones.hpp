#pragma once
// Rigid impact zones (BFA 2002 section 7.4), the fail-safe after the CCD impulses: the vertices
// of every pair still colliding are merged into zones (zones only grow during a step), and each
// zone's motion over the step is replaced by one rigid body motion that keeps its linear and
// angular momentum, with the inertia tensor of its vertex masses. A zone holding a vertex of
// infinite mass follows the rigid motion fitted to its infinite-mass vertices instead (a pinned
// vertex at rest makes the zone immovable). Detection repeats until the motion is clean.
//
// With a strain limit, an edge over it (strain_limiting.hpp, edge_over_limit) is merged like a
// colliding pair: both ends join one zone, whose rigid motion keeps the edge at its start
// length. The Gauss-Seidel limiter runs before the zones; this catches what it could not finish
// and what the zones' rigid motions stretch (an edge from a zone to a free vertex), so a step
// that ends clean ends with every edge within the limit. The zones grow through such edges one
// ring of vertices a pass; when the passes run out with only edges over the limit left, the
// free vertices are pulled to the held zones instead (resolve_impact_zones below).
#include <vector>

#include "collision/candidates.hpp"
#include "collision/ccd_response.hpp"
#include "collision/collision_step.hpp"
#include "collision/contact_pairs.hpp"
#include "collision/strain_limiting.hpp"

namespace weft {

// Scratch reused from step to step so that the zone passes do not allocate once warmed up.
struct ImpactZoneWorkspace {
  std::vector<int> parent;    // union-find forest over vertices (n_vertices)
  std::vector<int> members;   // vertices in zones of two or more, grouped by zone
  std::vector<char> in_zone;  // whether a vertex is listed in `members` (n_vertices)
  std::vector<int> stretched;  // edges over the strain limit in the current pass
  CcdCollisions collisions;
  // The last resort's copies (impact_zones.cpp, pull_free_vertices_to_zones): the inverse masses
  // with the zone vertices held, and the motion to restore if the pull is not clean.
  Eigen::VectorXd held_inverse_mass;
  Positions saved_x_end;
  Positions saved_velocity;
};

struct ImpactZoneResult {
  int passes = 0;         // detection passes run
  int zones = 0;          // zones of two or more vertices at the end
  int zone_vertices = 0;  // vertices in those zones
  bool clean = false;     // the final motion has no collision and no edge over the strain limit
  bool collision_free = false;  // the final motion has no collision (edges may be over the limit)
  bool stopped = false;   // the pass limit was reached and free vertices were stopped (x_end = x_start)
  int held = 0;           // holdable infinite-mass vertices (pins) held at their start, as a last resort
  bool pulled = false;    // the passes were spent on edges over the limit, and pulling the free
                          // vertices to the held zones made the motion clean (it was kept)
};

// Rigid motion of the given vertices over the step, fitted to their current motion (see above),
// written to x_end and velocity of the vertices with finite mass.
void apply_rigid_motion(CollisionStep& step, const int* vertices, int count);

// Detects and merges zones up to settings.max_impact_zone_passes times. If collisions remain,
// the vertices in zones, then if needed every vertex of finite mass, then the holdable
// infinite-mass ones (step.holdable: pins), stop for the step: starting from a state without
// intersection this ends so unless vertices that cannot be held (colliders) collide.
// If only edges over `strain`'s limit (when given) remain, the free vertices are pulled to the
// held zones by the limiter's sweeps, kept if that makes the motion clean (result.pulled). If it
// does not, the collision-free motion before the pull is kept and the result is collision-free but
// not clean: a zone holding infinite-mass vertices that move non-rigidly with respect to each
// other (a fixed and a turning pinned edge) has no rigid motion that follows them all, and its
// edges to them can stay over the limit.
// `first_pass`, when given, holds the pairs the first detection tests: the caller knows every
// other candidate free of collisions on the motion as given (a subset of the candidates, in their
// order, so that the collisions found are those testing them all would find).
ImpactZoneResult resolve_impact_zones(CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                                      const std::vector<EdgeEdgePair>& edge_edges,
                                      const ResponseSettings& settings, ImpactZoneWorkspace& workspace,
                                      const StrainBound* strain = nullptr,
                                      const CollisionCandidates* first_pass = nullptr);

}  // namespace weft
