#pragma once
// Cloth vertices inside a collider moved out of it, along the collider's outward normal: the
// collider half of untangling (untangling.hpp is the cloth-cloth half). A vertex is inside when
// it is inside the analytic solid or between the solid and the triangles that stand for it in the
// collision pipeline (collider_geometry.hpp: sphere and capsule facets lie outside the solid), so
// that the collision response, which sees those triangles, does not hold it in.
#include "collision/collider.hpp"
#include "core/math.hpp"

namespace weft {

struct ColliderPushOut {
  int moved = 0;          // free vertices given a displacement
  int pinned_inside = 0;  // vertices of zero inverse mass inside, which cannot move
  int first_pinned = -1;  // the first of them
  double deepest = 0.0;   // m, the largest push
};

// Whether the collider encloses a solid that a vertex can be inside: meshes and open cylinders
// do not.
bool collider_has_inside(const Collider& collider);

// For the vertices x (3 x n) of one cloth (triangles `cloth_triangles`) against one collider at
// time t whose surface triangles are posed at `surface` (3 x n_surface_vertices): the displacement
// (3 x n, added to) that takes each free vertex inside to `margin` outside the collider's
// triangles. The inside vertices joined by cloth edges move along one direction, the mean outward
// normal of the solid at those of them next to the outside (where the cloth enters), so a cloth
// deep in a box comes out through the face it entered by, in one piece; a region with no vertex
// outside beside it moves along each vertex's own normal.
ColliderPushOut push_out_of_collider(const Collider& collider, double t, const Positions& surface,
                                     const Triangles& surface_triangles, Eigen::Ref<const Positions> x,
                                     const Triangles& cloth_triangles, const Eigen::VectorXd& inverse_mass,
                                     double margin, Eigen::Ref<Positions> displacement);

}  // namespace weft
