#pragma once
// Analytic colliders: static solids of infinite mass the cloth cannot enter.
#include <string>

#include "core/math.hpp"

namespace weft {

enum class ColliderShape { plane, sphere, box };

struct Collider {
  std::string name;
  ColliderShape shape = ColliderShape::plane;
  Vec3 center = Vec3::Zero();         // plane: a point on it; sphere, box: the centre
  Vec3 normal = Vec3::UnitY();        // plane only: unit normal pointing out of the solid
  double radius = 0.5;                // sphere only
  Vec3 half_extents = Vec3::Constant(0.5);  // box only, axis-aligned
  double friction = 0.3;              // Coulomb coefficient against cloth
};

// Signed distance from p to the collider's surface (negative inside) and the outward unit
// normal of the closest surface point.
double signed_distance(const Collider& collider, const Vec3& p, Vec3& outward_normal);

const char* to_string(ColliderShape shape);

}  // namespace weft
