#pragma once
// Colliders: solids of infinite mass that cloths and soft bodies cannot enter. Each is either an
// analytic shape (plane, sphere, box, capsule, cylinder) or a triangle mesh from an OBJ file,
// static or kinematic (a scripted translation plus a rotation about an axis). The collision
// pipeline sees every collider as a triangle mesh (collider_geometry.hpp) whose vertices move
// with the collider and never yield; the analytic description stays the reference for checks.
#include <string>

#include "core/math.hpp"
#include "core/triangle_mesh.hpp"

namespace weft {

enum class ColliderShape { plane, sphere, box, capsule, cylinder, mesh };

// Scripted rigid motion: a point x of the collider at time 0 is at
// R(axis, angular_velocity t) (x - pivot) + pivot + velocity t at time t.
struct ColliderMotion {
  Vec3 velocity = Vec3::Zero();  // m/s
  Vec3 pivot = Vec3::Zero();     // m, a point on the rotation axis at time 0
  Vec3 axis = Vec3::UnitY();     // unit
  double angular_velocity = 0.0; // rad/s

  bool is_static() const { return velocity.isZero(0.0) && angular_velocity == 0.0; }
  // Rotation and translation that carry the collider from time 0 to time t.
  Mat3 rotation(double t) const;
  Vec3 translation(double t) const;
  // Where a point, or each column of `rest` (both given at time 0), is at time t.
  Vec3 place(const Vec3& point, double t) const { return rotation(t) * point + translation(t); }
  void place(const Positions& rest, double t, Eigen::Ref<Positions> out) const {
    out.noalias() = rotation(t) * rest;  // into `out`: no temporary (called every step)
    out.colwise() += translation(t);
  }
};

struct Collider {
  std::string name;
  ColliderShape shape = ColliderShape::plane;
  Vec3 center = Vec3::Zero();         // plane: a point on it; other shapes: the centre
  Vec3 normal = Vec3::UnitY();        // plane: unit normal pointing out of the solid
  double radius = 0.5;                // sphere, capsule, cylinder
  Vec3 half_extents = Vec3::Constant(0.5);  // box, axis-aligned before any motion
  Vec3 axis = Vec3::UnitY();          // capsule, cylinder: unit direction of the axis
  double half_length = 0.5;           // capsule: half the segment's length; cylinder: half the height
  bool capped = true;                 // cylinder: closed by two end disks, or an open tube
  double plane_half_size = 10.0;      // plane: the square standing for it, m from the point to an edge
  TriangleMesh mesh;                  // mesh: the triangles, in scene coordinates at time 0
  std::string obj_file;               // mesh: where the triangles came from (for the scene file)
  double static_friction = 0.3;       // Coulomb coefficient against cloth below which sliding stops
  double friction = 0.3;              // Coulomb coefficient against cloth while sliding (kinetic)
  ColliderMotion motion;              // static unless set
};

// Signed distance from p to the collider's surface at time 0 (negative inside) and the outward
// unit normal of the closest surface point. Cylinders count as solids; meshes are not supported
// (returns +infinity).
double signed_distance(const Collider& collider, const Vec3& p, Vec3& outward_normal);

// The same at time t: p is carried back by the inverse of the collider's motion.
double signed_distance_at(const Collider& collider, const Vec3& p, double t);

const char* to_string(ColliderShape shape);

}  // namespace weft
