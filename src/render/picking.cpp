#include "render/picking.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace weft {

Ray camera_ray(const OrbitCamera& camera, double aspect, double ndc_x, double ndc_y) {
  const Eigen::Matrix4d inverse =
      (camera.projection_matrix(aspect).cast<double>() * camera.view_matrix().cast<double>()).inverse();
  const Eigen::Vector4d near_point = inverse * Eigen::Vector4d(ndc_x, ndc_y, -1.0, 1.0);
  const Eigen::Vector4d far_point = inverse * Eigen::Vector4d(ndc_x, ndc_y, 1.0, 1.0);
  const Vec3 a = near_point.head<3>() / near_point.w();
  const Vec3 b = far_point.head<3>() / far_point.w();
  return {camera.eye(), (b - a).normalized()};
}

namespace {

// Moeller-Trumbore: distance along the ray to the triangle, or a negative number for a miss.
double intersect(const Ray& ray, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 p = ray.direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14) return -1.0;
  const Vec3 s = ray.origin - p0;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Vec3 q = s.cross(e1);
  const double v = ray.direction.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  return e2.dot(q) / det;
}

// Distance along the ray to where it enters the box (0 if it starts inside), or +infinity for a
// miss (slab test; a zero direction component divides to +-infinity, which the min/max absorb,
// or to NaN when the origin lies on that slab's face, where the ray stays in the slab).
double enter_box(const Ray& ray, const Vec3& inverse_direction, const Aabb& box) {
  double near = 0.0;
  double far = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    double t0 = (box.lower[k] - ray.origin[k]) * inverse_direction[k];
    double t1 = (box.upper[k] - ray.origin[k]) * inverse_direction[k];
    if (t0 > t1) std::swap(t0, t1);
    if (std::isnan(t0) || std::isnan(t1)) continue;  // parallel to the slab, starting on its face: inside
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far ? near : std::numeric_limits<double>::infinity();
}

bool matches(const Bvh& bvh, const Cloth& cloth) {
  return bvh.num_vertices() == cloth.num_vertices() && bvh.triangles().cols() == cloth.model.triangles.cols();
}

}  // namespace

std::optional<VertexPick> pick_vertex(const std::vector<Cloth>& cloths, const Ray& ray,
                                      const std::vector<Bvh>* bvhs) {
  VertexPick best;
  best.distance = std::numeric_limits<double>::infinity();
  int best_triangle = -1;
  const Vec3 inverse_direction = ray.direction.cwiseInverse();
  for (size_t c = 0; c < cloths.size(); ++c) {
    const Positions& x = cloths[c].state.x;
    const Triangles& triangles = cloths[c].model.triangles;
    const auto test = [&](int t) {
      const double distance = intersect(ray, x.col(triangles(0, t)), x.col(triangles(1, t)), x.col(triangles(2, t)));
      if (distance > 0.0 && distance < best.distance) {
        best.distance = distance;
        best.cloth = static_cast<int>(c);
        best_triangle = t;
      }
    };
    if (!bvhs || c >= bvhs->size() || !matches((*bvhs)[c], cloths[c])) {
      for (int t = 0; t < triangles.cols(); ++t) test(t);
      continue;
    }
    // Preorder walk of the flat hierarchy: a node the ray misses, or enters beyond the best hit
    // so far, is skipped with its subtree (`next`).
    const Bvh& bvh = (*bvhs)[c];
    const std::vector<BvhNode>& nodes = bvh.nodes();
    for (size_t n = 0; n < nodes.size();) {
      const BvhNode& node = nodes[n];
      if (enter_box(ray, inverse_direction, node.box) > best.distance) {
        n = static_cast<size_t>(node.next);
        continue;
      }
      if (node.is_leaf()) {
        for (int k = node.first; k < node.first + node.count; ++k) test(bvh.triangle_order()[k]);
      }
      ++n;
    }
  }
  if (best_triangle < 0) return std::nullopt;
  const Cloth& cloth = cloths[static_cast<size_t>(best.cloth)];
  best.hit = ray.origin + best.distance * ray.direction;
  double nearest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const int vertex = cloth.model.triangles(k, best_triangle);
    const double d = (cloth.state.x.col(vertex) - best.hit).squaredNorm();
    if (d < nearest) {
      nearest = d;
      best.vertex = vertex;
    }
  }
  return best;
}

Vec3 point_on_view_plane(const Ray& ray, const Vec3& point, const Vec3& view_direction) {
  const double denominator = ray.direction.dot(view_direction);
  if (std::abs(denominator) < 1e-12) return point;
  return ray.origin + ((point - ray.origin).dot(view_direction) / denominator) * ray.direction;
}

}  // namespace weft
