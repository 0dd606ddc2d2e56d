#include "collision/collider_push_out.hpp"

#include <algorithm>
#include <limits>

#include "collision/edge_triangle_crossing.hpp"

namespace weft {

bool collider_has_inside(const Collider& collider) {
  if (collider.shape == ColliderShape::mesh) return false;
  if (collider.shape == ColliderShape::cylinder && !collider.capped) return false;
  return true;
}

namespace {

// How far outside the solid the collider's triangles can lie (collider_geometry.hpp): the
// circumscribed facets of spheres and capsules stay within a few percent of the radius.
double facet_gap(const Collider& collider) {
  switch (collider.shape) {
    case ColliderShape::sphere:
    case ColliderShape::capsule:
      return 0.05 * collider.radius;
    default:
      return 0.0;
  }
}

// Distance along `direction` from p to where it leaves the triangles (the first crossing
// within `reach`), or -1 when the ray crosses none.
double exit_distance(const Vec3& p, const Vec3& direction, double reach, const Positions& surface,
                     const Triangles& triangles) {
  const Vec3 to = p + reach * direction;
  const Vec3 lower = p.cwiseMin(to);
  const Vec3 upper = p.cwiseMax(to);
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Vec3 a = surface.col(triangles(0, t));
    const Vec3 b = surface.col(triangles(1, t));
    const Vec3 c = surface.col(triangles(2, t));
    if ((a.cwiseMax(b).cwiseMax(c).array() < lower.array()).any()) continue;
    if ((a.cwiseMin(b).cwiseMin(c).array() > upper.array()).any()) continue;
    if (const auto crossing = edge_triangle_crossing(p, to, a, b, c))
      nearest = std::min(nearest, crossing->s * reach);
  }
  return nearest < std::numeric_limits<double>::infinity() ? nearest : -1.0;
}

}  // namespace

ColliderPushOut push_out_of_collider(const Collider& collider, double t, const Positions& surface,
                                     const Triangles& surface_triangles, Eigen::Ref<const Positions> x,
                                     const Eigen::VectorXd& inverse_mass, double margin,
                                     Eigen::Ref<Positions> displacement) {
  ColliderPushOut result;
  if (!collider_has_inside(collider)) return result;
  const Mat3 rotation = collider.motion.rotation(t);
  const Vec3 translation = collider.motion.translation(t);
  const double gap = facet_gap(collider);
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    const Vec3 p = x.col(v);
    Vec3 rest_normal;
    const double distance = signed_distance(collider, rotation.transpose() * (p - translation), rest_normal);
    if (!(distance < gap)) continue;
    const Vec3 normal = rotation * rest_normal;
    // Inside the triangles: the ray out along the normal crosses them (the solid is convex).
    const double reach = std::max(0.0, -distance) + gap + margin;
    double push = exit_distance(p, normal, reach, surface, surface_triangles);
    if (push < 0.0) {
      if (distance >= 0.0) continue;  // outside both
      push = -distance;               // inside the solid, on a face the triangles follow exactly
    }
    if (inverse_mass(v) == 0.0) {
      if (result.pinned_inside == 0) result.first_pinned = static_cast<int>(v);
      ++result.pinned_inside;
      continue;
    }
    displacement.col(v) += (push + margin) * normal;
    result.deepest = std::max(result.deepest, push + margin);
    ++result.moved;
  }
  return result;
}

}  // namespace weft
