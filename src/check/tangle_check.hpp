#pragma once
// Whether a state is tangled: cloth triangles that intersect each other (between two cloths or
// within one, by the standard definition of intersection_check.hpp) or a collider's surface, and
// cloth vertices inside a collider's solid (solid_distance.hpp). Every run checks its frames with
// it, and `weft check DIR` checks a recording; neither uses the collision code's filters.
#include <string>
#include <vector>

#include "check/intersection_check.hpp"
#include "check/solid_distance.hpp"

namespace weft {

// A named surface to check; refers to data the caller keeps alive.
struct NamedSurface {
  std::string name;
  const Positions* positions = nullptr;  // (3 x n_vertices)
  const Triangles* triangles = nullptr;  // (3 x n_triangles)
};

// What one state is checked from: cloths, colliders' surfaces (as triangles) and, for the
// colliders that have an inside, their solids.
struct TangleInput {
  std::vector<NamedSurface> cloths;
  std::vector<NamedSurface> colliders;
  std::vector<AnalyticSolid> solids;  // one per collider with an inside
  std::vector<int> solid_collider;    // per solid: its collider's index in `colliders`
  // Per cloth, per solid: 1 where the solid holds the cloth (a drum), whose vertices inside it
  // then do not count; empty: none is held.
  std::vector<std::vector<char>> held;
};

// Which solids hold which cloths: those that more than half of a cloth's vertices are inside.
// A run decides it from its first state: a cloth placed in a drum is held by it, one merely
// dipping into a sphere is not.
std::vector<std::vector<char>> solids_holding_cloths(const TangleInput& input);

// Intersecting triangle pairs between two surfaces (or within one: surface_a == surface_b).
// Surfaces are numbered cloths first, then colliders.
struct SurfacePairTangle {
  int surface_a = 0;
  int surface_b = 0;
  int pairs = 0;
  int first_triangle_a = 0;  // the first pair in (surface, triangle) order
  int first_triangle_b = 0;
  Vec3 near = Vec3::Zero();  // m, the mean of the first pair's six corners
};

// Cloth vertices inside one collider's solid.
struct VerticesInsideSolid {
  int cloth = 0;
  int collider = 0;
  int vertices = 0;
  int deepest_vertex = 0;
  double deepest = 0.0;  // m below the surface
};

struct TangleReport {
  int intersecting_pairs = 0;                    // cloth-cloth, self and cloth-collider triangle pairs
  int vertices_inside_colliders = 0;             // (cloth vertex, collider) pairs with the vertex inside
  std::vector<SurfacePairTangle> surface_pairs;  // in (surface_a, surface_b) order
  std::vector<VerticesInsideSolid> inside;       // in (cloth, collider) order
  std::vector<TriangleIntersection> pairs;       // every intersecting pair (meshes numbered as surfaces)
  bool clean() const { return intersecting_pairs == 0 && vertices_inside_colliders == 0; }
};

// Checks one state. Throws std::invalid_argument on a null surface, an index out of range or a
// coordinate that is not finite.
TangleReport check_tangles(const TangleInput& input);

// The report in words, for one line of a log: which surfaces, how many pairs, the first pair
// and where; which cloth, how many vertices inside which collider, the deepest. Empty when clean.
std::string describe_tangles(const TangleReport& report, const TangleInput& input);

}  // namespace weft
