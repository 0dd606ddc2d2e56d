#pragma once
// Signed distance to an analytic solid, from the shape's definition alone: the judge of whether
// a point lies inside a collider, written apart from the collision code (which sees colliders
// as triangle meshes) so that a check shares nothing with what it checks.
//
// Shapes are closed solids: a half-space (a plane collider's solid side), a sphere, a box, a
// capsule and a capped cylinder. Triangle meshes and open tubes have no inside here: an OBJ
// mesh is closed only when every edge joins exactly two consistently oriented triangles and no
// two triangles cross, which a mesh from another tool rarely guarantees.
#include "core/math.hpp"

namespace weft {

enum class SolidKind { half_space, sphere, box, capsule, capped_cylinder };

// A solid in its own frame (centred at the origin; box axis-aligned; capsule and cylinder
// along `axis`), placed in the scene by `orientation` and `center`: a point y of the solid's
// frame is at orientation * y + center.
struct AnalyticSolid {
  SolidKind kind = SolidKind::sphere;
  Vec3 normal = Vec3::UnitY();              // half_space: unit normal pointing out of the solid
  double radius = 0.5;                      // sphere, capsule, capped_cylinder
  Vec3 half_extents = Vec3::Constant(0.5);  // box
  Vec3 axis = Vec3::UnitY();                // capsule, capped_cylinder: unit direction
  double half_length = 0.5;                 // capsule: half the segment; capped_cylinder: half the height
  Mat3 orientation = Mat3::Identity();      // rotation from the solid's frame to the scene's
  Vec3 center = Vec3::Zero();               // m, where the solid's origin is in the scene
};

// Signed distance from p to the solid's surface, m: negative inside, 0 on the surface.
double reference_signed_distance(const AnalyticSolid& solid, const Vec3& p);

}  // namespace weft
