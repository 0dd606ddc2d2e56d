#include "collision/placeholder_contact.hpp"

namespace weft {

int resolve_placeholder_contacts(Cloth& cloth, const std::vector<Collider>& colliders, double /*h*/,
                                 std::vector<ContactRecord>* records) {
  ClothState& state = cloth.state;
  const double thickness = cloth.model.thickness;
  int contacts = 0;
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    if (cloth.model.inverse_mass[i] == 0.0) continue;  // pinned
    for (const Collider& collider : colliders) {
      Vec3 normal;
      const double distance = signed_distance(collider, state.x.col(i), normal);
      if (distance >= thickness) continue;
      ++contacts;
      // Project onto the surface offset by the thickness.
      state.x.col(i) += (thickness - distance) * normal;
      // Remove the approaching normal velocity (inelastic) and apply Coulomb friction:
      // the tangential speed drops by mu times the normal speed removed, never reversing.
      const double normal_speed = state.v.col(i).dot(normal);
      if (records != nullptr) {
        ContactRecord record;
        record.position = state.x.col(i);
        record.kind = ContactKind::vertex_face;
        record.depth = thickness - distance;
        record.impulse = normal_speed < 0.0 ? cloth.model.mass[i] * -normal_speed : 0.0;
        record.primitive_a = i;
        record.normal = normal;
        record.with_solid = true;
        records->push_back(record);
      }
      if (normal_speed < 0.0) {
        const Vec3 tangential = state.v.col(i) - normal_speed * normal;
        const double tangential_speed = tangential.norm();
        const double reduction = collider.friction * -normal_speed;
        state.v.col(i) = tangential_speed > reduction
                             ? Vec3(tangential * (1.0 - reduction / tangential_speed))
                             : Vec3::Zero();
      }
    }
  }
  return contacts;
}

}  // namespace weft
