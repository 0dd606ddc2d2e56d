#include "render/debug_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

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

Color contact_color(ContactKind kind, ContactPartners partners) {
  const bool vertex_face = kind == ContactKind::vertex_face;
  switch (partners) {
    case ContactPartners::cloth_solid:
      return vertex_face ? Color(1.0f, 0.2f, 0.2f) : Color(0.3f, 1.0f, 0.3f);  // red, green
    case ContactPartners::cloth_cloth:
      return vertex_face ? Color(1.0f, 0.95f, 0.2f) : Color(0.2f, 1.0f, 0.9f);  // yellow, cyan
    case ContactPartners::soft_body:
      break;
  }
  return vertex_face ? Color(1.0f, 0.55f, 0.1f) : Color(0.8f, 0.3f, 1.0f);  // orange, violet
}

double contact_arrow_scale(double largest_impulse, double impulse_scale, double max_arrow_length) {
  const double longest = impulse_scale * std::abs(largest_impulse);
  if (!(longest > max_arrow_length) || !std::isfinite(longest)) return impulse_scale;
  return max_arrow_length / std::abs(largest_impulse);
}

void add_contacts(DebugOverlay& overlay, const std::vector<ContactRecord>& contacts, double impulse_scale,
                  double max_arrow_length) {
  double largest_impulse = 0.0;
  for (const ContactRecord& contact : contacts) largest_impulse = std::max(largest_impulse, std::abs(contact.impulse));
  const double arrow_scale = contact_arrow_scale(largest_impulse, impulse_scale, max_arrow_length);
  for (const ContactRecord& contact : contacts) {
    const Color color = contact_color(contact.kind, contact.partners);
    overlay.points.push_back({contact.position, color, 7.0f});
    const Vec3 arrow = arrow_scale * contact.impulse * contact.normal;
    if (!arrow.isZero(0.0)) overlay.add_arrow(contact.position, contact.position + arrow, color);
  }
}

std::vector<Eigen::AlignedBox3d> bvh_boxes_at_depth(const Bvh& bvh, int depth) {
  std::vector<Eigen::AlignedBox3d> boxes;
  const std::vector<BvhNode>& nodes = bvh.nodes();
  if (nodes.empty()) return boxes;
  // Preorder walk: the left child is the next node, the right one is stored.
  std::vector<std::pair<int, int>> stack{{0, 0}};  // (node, its depth)
  while (!stack.empty()) {
    const auto [index, node_depth] = stack.back();
    stack.pop_back();
    const BvhNode& node = nodes[static_cast<size_t>(index)];
    if (node_depth >= depth || node.is_leaf()) {
      boxes.emplace_back(node.box.lower, node.box.upper);
      continue;
    }
    stack.push_back({node.right, node_depth + 1});
    stack.push_back({index + 1, node_depth + 1});
  }
  return boxes;
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
