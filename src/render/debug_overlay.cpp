#include "render/debug_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace weft {

void DebugOverlay::add_box(const Eigen::AlignedBox3d& box, const Color& color) {
  if (box.isEmpty()) return;
  const Vec3 lo = box.min(), hi = box.max();
  const auto corner = [&](int k) {
    return Vec3((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  };
  // Corners k and k | bit differ along one axis: those pairs are the edges.
  for (int k = 0; k < 8; ++k) {
    for (int bit : {1, 2, 4}) {
      if ((k & bit) == 0) add_line(corner(k), corner(k | bit), color);
    }
  }
}

void DebugOverlay::add_arrow(const Vec3& from, const Vec3& to, const Color& color) {
  add_line(from, to, color);
  const Vec3 shaft = to - from;
  const double length = shaft.norm();
  if (length <= 0.0) return;
  const Vec3 direction = shaft / length;
  // Two barbs in a plane containing the shaft.
  const Vec3 helper = std::abs(direction.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  const Vec3 side = direction.cross(helper).normalized();
  const double head = 0.25 * length;
  add_line(to, to - head * direction + 0.5 * head * side, color);
  add_line(to, to - head * direction - 0.5 * head * side, color);
}

Color contact_color(ContactKind kind, ContactPair pair) {
  const bool cloth_cloth = pair == ContactPair::cloth_cloth;
  if (kind == ContactKind::vertex_face) {
    return cloth_cloth ? Color(1.0f, 0.95f, 0.2f) : Color(1.0f, 0.2f, 0.2f);  // yellow, red
  }
  return cloth_cloth ? Color(0.2f, 1.0f, 0.9f) : Color(0.3f, 1.0f, 0.3f);  // cyan, green
}

void add_contacts(DebugOverlay& overlay, const std::vector<ContactRecord>& contacts, double arrow_scale) {
  for (const ContactRecord& contact : contacts) {
    const Color color = contact_color(contact.kind, contact.pair);
    overlay.points.push_back({contact.position, color, 7.0f});
    if (!contact.impulse.isZero(0.0)) {
      overlay.add_arrow(contact.position, contact.position + arrow_scale * contact.impulse, color);
    }
  }
}

namespace {

Eigen::AlignedBox3d triangle_box(const Positions& x, const Triangles& triangles, int t) {
  Eigen::AlignedBox3d box;
  for (int k = 0; k < 3; ++k) box.extend(Vec3(x.col(triangles(k, t))));
  return box;
}

void split_to_depth(const Positions& x, const Triangles& triangles, const Positions& centroids,
                    std::vector<int>::iterator begin, std::vector<int>::iterator end, int depth,
                    std::vector<Eigen::AlignedBox3d>& boxes) {
  Eigen::AlignedBox3d box;
  for (auto it = begin; it != end; ++it) box.extend(triangle_box(x, triangles, *it));
  if (depth == 0 || end - begin <= 1) {
    boxes.push_back(box);
    return;
  }
  int axis = 0;
  box.diagonal().maxCoeff(&axis);
  const auto middle = begin + (end - begin) / 2;
  std::nth_element(begin, middle, end, [&](int a, int b) { return centroids(axis, a) < centroids(axis, b); });
  split_to_depth(x, triangles, centroids, begin, middle, depth - 1, boxes);
  split_to_depth(x, triangles, centroids, middle, end, depth - 1, boxes);
}

}  // namespace

std::vector<Eigen::AlignedBox3d> triangle_boxes_at_depth(const Positions& x, const Triangles& triangles,
                                                         int depth) {
  std::vector<Eigen::AlignedBox3d> boxes;
  const int count = static_cast<int>(triangles.cols());
  if (count == 0) return boxes;
  Positions centroids(3, count);
  for (int t = 0; t < count; ++t) {
    centroids.col(t) = (x.col(triangles(0, t)) + x.col(triangles(1, t)) + x.col(triangles(2, t))) / 3.0;
  }
  std::vector<int> order(static_cast<size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  split_to_depth(x, triangles, centroids, order.begin(), order.end(), std::max(depth, 0), boxes);
  return boxes;
}

Eigen::AlignedBox3d collider_bounds(const Collider& collider) {
  switch (collider.shape) {
    case ColliderShape::sphere:
      return {collider.center - Vec3::Constant(collider.radius), collider.center + Vec3::Constant(collider.radius)};
    case ColliderShape::box:
      return {collider.center - collider.half_extents, collider.center + collider.half_extents};
    case ColliderShape::plane:
      break;
  }
  return Eigen::AlignedBox3d();
}

void add_pins(DebugOverlay& overlay, const Cloth& cloth, const Color& color) {
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    if (cloth.model.inverse_mass[i] == 0.0) overlay.points.push_back({cloth.state.x.col(i), color, 9.0f});
  }
}

void add_ground_grid(DebugOverlay& overlay, const Collider& plane, const Vec3& anchor, double half_size,
                     double spacing, const Color& color) {
  if (plane.shape != ColliderShape::plane || spacing <= 0.0) return;
  const Vec3 normal = plane.normal.normalized();
  const Vec3 helper = std::abs(normal.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  const Vec3 u = normal.cross(helper).normalized();
  const Vec3 w = normal.cross(u);
  // Snap the centre to the grid so the lines do not swim when the anchor moves; lift them a hair
  // above the plane so they win the depth test against its surface.
  Vec3 center = anchor - normal.dot(anchor - plane.center) * normal;
  const double cu = spacing * std::round(u.dot(center - plane.center) / spacing);
  const double cw = spacing * std::round(w.dot(center - plane.center) / spacing);
  center = plane.center + cu * u + cw * w + 1e-3 * spacing * normal;
  const int lines = static_cast<int>(std::floor(half_size / spacing));
  for (int k = -lines; k <= lines; ++k) {
    const double offset = k * spacing;
    overlay.add_line(center + offset * u - half_size * w, center + offset * u + half_size * w, color);
    overlay.add_line(center + offset * w - half_size * u, center + offset * w + half_size * u, color);
  }
}

}  // namespace weft
