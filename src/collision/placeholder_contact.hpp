#pragma once
// PLACEHOLDER contact until the collision issue lands (BVH, CCD, impact zones): after the
// integrator has moved the cloth, every vertex closer than `thickness` to an analytic
// collider is projected back onto the offset surface, its inward normal velocity removed and
// its tangential velocity reduced by Coulomb friction. Cloth-cloth contact is not handled.
#include <vector>

#include "collision/collider.hpp"
#include "collision/contact_record.hpp"
#include "physics/cloth.hpp"

namespace weft {

// Returns the number of vertices that were in contact; appends one vertex-face, cloth-solid
// record per contact to `records` when it is not null.
int resolve_placeholder_contacts(Cloth& cloth, const std::vector<Collider>& colliders, double h,
                                 std::vector<ContactRecord>* records = nullptr);

}  // namespace weft
