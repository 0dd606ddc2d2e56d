#pragma once
// What the renderer draws over the scene for debugging: coloured line segments (bounding boxes,
// arrows, the ground grid) and coloured points (contacts, pins). Plain data, no OpenGL: the viewer
// fills it from the World, tests fill it by hand.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/math.hpp"
#include "physics/cloth.hpp"
#include "collision/collider.hpp"

namespace weft {

using Color = Eigen::Vector3f;  // linear RGB in [0, 1]

struct OverlayLine {
  Vec3 from, to;
  Color color;
};

struct OverlayPoint {
  Vec3 position;
  Color color;
  float size = 6.0f;  // pixels across
};

struct DebugOverlay {
  std::vector<OverlayLine> lines;
  std::vector<OverlayPoint> points;

  void clear() {
    lines.clear();
    points.clear();
  }
  void add_line(const Vec3& from, const Vec3& to, const Color& color) { lines.push_back({from, to, color}); }
  // The twelve edges of an axis-aligned box.
  void add_box(const Eigen::AlignedBox3d& box, const Color& color);
  // A shaft from `from` to `to` with a small head at `to`.
  void add_arrow(const Vec3& from, const Vec3& to, const Color& color);
};

// Contacts as the collision module will report them; the viewer draws whatever list it gets.
enum class ContactKind { vertex_face, edge_edge };
enum class ContactPair { cloth_cloth, cloth_solid };

struct ContactRecord {
  ContactKind kind = ContactKind::vertex_face;
  ContactPair pair = ContactPair::cloth_solid;
  Vec3 position = Vec3::Zero();  // m, where the contact acts
  Vec3 impulse = Vec3::Zero();   // N s, applied to the cloth at `position`
};

// Colour of a contact: vertex-face warm, edge-edge cool; cloth-cloth brighter than cloth-solid.
Color contact_color(ContactKind kind, ContactPair pair);

// Contact points coloured by kind, each with its impulse as an arrow `arrow_scale` m per N s long.
void add_contacts(DebugOverlay& overlay, const std::vector<ContactRecord>& contacts, double arrow_scale);

// Bounding boxes of a cloth's triangles at hierarchy depth `depth` (0: one box round the cloth):
// each level splits a node's triangles in two at the median centroid along the box's longest axis.
// A stand-in until the collision module's BVH is exposed; leaves stop splitting at one triangle.
std::vector<Eigen::AlignedBox3d> triangle_boxes_at_depth(const Positions& x, const Triangles& triangles,
                                                         int depth);

// Bounding box of a sphere or box collider; empty for a plane (unbounded).
Eigen::AlignedBox3d collider_bounds(const Collider& collider);

// Pinned vertices (inverse mass 0) of a cloth as points.
void add_pins(DebugOverlay& overlay, const Cloth& cloth, const Color& color);

// A square grid of lines on a plane collider, centred on the point of the plane nearest `anchor`,
// `half_size` m from the centre to each side with lines every `spacing` m.
void add_ground_grid(DebugOverlay& overlay, const Collider& plane, const Vec3& anchor, double half_size,
                     double spacing, const Color& color);

}  // namespace weft
