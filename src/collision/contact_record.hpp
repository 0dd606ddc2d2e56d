#pragma once
// One contact the collision response acted on, kept so the viewer can draw it and the stats
// can count it.
#include "core/math.hpp"

namespace weft {

enum class ContactKind { vertex_face, edge_edge };

struct ContactRecord {
  Vec3 position = Vec3::Zero();  // vertex (vertex-face) or closest point on edge_a (edge-edge)
  ContactKind kind = ContactKind::vertex_face;
  double depth = 0.0;    // thickness minus distance when acted on (m); about the thickness for CCD hits
  double impulse = 0.0;  // magnitude of the normal impulse applied (kg m/s)
  int primitive_a = -1;  // vertex (vertex-face) or edge_a (edge-edge)
  int primitive_b = -1;  // triangle (vertex-face) or edge_b (edge-edge)
};

}  // namespace weft
