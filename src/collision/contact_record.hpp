#pragma once
// One contact the collision response acted on, kept so the viewer can draw it and the stats
// can count it.
#include "core/math.hpp"

namespace weft {

enum class ContactKind { vertex_face, edge_edge };

// What touched: two cloths (or one cloth itself), a cloth and a collider, or a soft body (a
// closed mesh with pressure) and anything.
enum class ContactPartners { cloth_cloth, cloth_solid, soft_body };

struct ContactRecord {
  Vec3 position = Vec3::Zero();  // vertex (vertex-face) or closest point on edge_a (edge-edge)
  ContactKind kind = ContactKind::vertex_face;
  double depth = 0.0;    // thickness minus distance when acted on (m); about the thickness for CCD hits
  double impulse = 0.0;  // magnitude of the normal impulse applied (kg m/s)
  int primitive_a = -1;  // vertex (vertex-face) or edge_a (edge-edge)
  int primitive_b = -1;  // triangle (vertex-face) or edge_b (edge-edge)
  ContactPartners partners = ContactPartners::cloth_cloth;  // set by the world, which knows the meshes
  Vec3 normal = Vec3::Zero();  // unit direction of the impulse on the vertex / edge_a; zero if not recorded
};

}  // namespace weft
