#include "collision/collider_push_out.hpp"

#include <algorithm>
#include <limits>
#include <vector>

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
                                     const Triangles& cloth_triangles, const Eigen::VectorXd& inverse_mass,
                                     double margin, Eigen::Ref<Positions> displacement) {
  ColliderPushOut result;
  if (!collider_has_inside(collider) || surface.cols() == 0) return result;
  const Mat3 rotation = collider.motion.rotation(t);
  const Vec3 translation = collider.motion.translation(t);
  const double gap = facet_gap(collider);
  const int n = static_cast<int>(x.cols());

  // Which vertices are inside, with the solid's outward normal at each.
  std::vector<char> inside(static_cast<size_t>(n), 0);
  std::vector<Vec3> normal(static_cast<size_t>(n), Vec3::Zero());
  for (int v = 0; v < n; ++v) {
    const Vec3 p = x.col(v);
    Vec3 rest_normal;
    const double distance = signed_distance(collider, rotation.transpose() * (p - translation), rest_normal);
    if (!(distance < gap)) continue;
    normal[v] = rotation * rest_normal;
    // Inside the triangles: the ray out along the normal crosses them (the solid is convex).
    const double reach = std::max(0.0, -distance) + gap + margin;
    inside[v] = distance < 0.0 || exit_distance(p, normal[v], reach, surface, surface_triangles) >= 0.0;
  }

  // Regions of inside vertices joined by cloth edges; each leaves along one direction, the mean
  // normal of its vertices next to the outside (where it entered), so that a region deep in a box
  // is not torn between faces. A region with no such vertex leaves along each vertex's normal.
  std::vector<int> parent(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) parent[v] = v;
  const auto root = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<char> on_edge(static_cast<size_t>(n), 0);  // inside, with an outside neighbour
  for (Eigen::Index f = 0; f < cloth_triangles.cols(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = cloth_triangles(k, f);
      const int b = cloth_triangles((k + 1) % 3, f);
      if (inside[a] && inside[b]) {
        const int ra = root(a);
        const int rb = root(b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      } else if (inside[a] != inside[b]) {
        on_edge[inside[a] ? a : b] = 1;
      }
    }
  }
  std::vector<Vec3> region_direction(static_cast<size_t>(n), Vec3::Zero());
  for (int v = 0; v < n; ++v) {
    if (on_edge[v]) region_direction[root(v)] += normal[v];
  }
  const Eigen::Vector3d low = surface.rowwise().minCoeff();
  const Eigen::Vector3d high = surface.rowwise().maxCoeff();
  const double across = (high - low).norm() + gap + margin;  // no exit is farther

  for (int v = 0; v < n; ++v) {
    if (!inside[v]) continue;
    if (inverse_mass(v) == 0.0) {
      if (result.pinned_inside == 0) result.first_pinned = v;
      ++result.pinned_inside;
      continue;
    }
    const Vec3 p = x.col(v);
    const Vec3& summed = region_direction[root(v)];
    Vec3 direction = summed.norm() > 1e-12 ? Vec3(summed.normalized()) : normal[v];
    double push = exit_distance(p, direction, across, surface, surface_triangles);
    if (push < 0.0) {  // on a face the triangles follow exactly: out along the vertex's own normal
      direction = normal[v];
      Vec3 rest_normal;
      push = std::max(0.0, -signed_distance(collider, rotation.transpose() * (p - translation), rest_normal));
    }
    displacement.col(v) += (push + margin) * direction;
    result.deepest = std::max(result.deepest, push + margin);
    ++result.moved;
  }
  return result;
}

}  // namespace weft
