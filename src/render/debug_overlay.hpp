#pragma once
// What the renderer draws over the scene for debugging: coloured line segments (bounding boxes,
// arrows, the ground grid) and coloured points (contacts, pins). Plain data, no OpenGL: the viewer
// fills it from the World, tests fill it by hand.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision/bvh.hpp"
#include "collision/collider.hpp"
#include "collision/contact_record.hpp"
#include "core/math.hpp"
#include "physics/cloth.hpp"

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

// Colour of a contact: vertex-face warm, edge-edge cool; one hue per kind of partners
// (cloth-solid, cloth-cloth, soft body).
Color contact_color(ContactKind kind, ContactPartners partners);

// Metres of contact arrow per N s of impulse: `impulse_scale`, unless the largest impulse's arrow
// would then be longer than `max_arrow_length` m; then all shrink together so that it is exactly
// that long. Dense contact keeps arrows in proportion to each other and short beside the scene.
double contact_arrow_scale(double largest_impulse, double impulse_scale, double max_arrow_length);

// Contact points coloured by kind, each with its impulse as an arrow along the record's normal,
// contact_arrow_scale(largest impulse, impulse_scale, max_arrow_length) m per N s long (no arrow
// where the record has no normal or no impulse).
void add_contacts(DebugOverlay& overlay, const std::vector<ContactRecord>& contacts, double impulse_scale,
                  double max_arrow_length);

// Boxes of the hierarchy's nodes at depth `depth` (0: the root), and of the leaves above it.
std::vector<Eigen::AlignedBox3d> bvh_boxes_at_depth(const Bvh& bvh, int depth);

// Pinned vertices (inverse mass 0) of a cloth as points.
void add_pins(DebugOverlay& overlay, const Cloth& cloth, const Color& color);

// A square grid of lines on a plane collider, centred on the point of the plane nearest `anchor`,
// `half_size` m from the centre to each side with lines every `spacing` m.
void add_ground_grid(DebugOverlay& overlay, const Collider& plane, const Vec3& anchor, double half_size,
                     double spacing, const Color& color);

}  // namespace weft
