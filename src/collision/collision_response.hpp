#pragma once
// The whole response of one step in BFA 2002 order: proximity impulses and friction (7.2), CCD
// impulse passes (7.3), then rigid impact zones (7.4) until the motion is clean.
#include <vector>

#include "collision/impact_zones.hpp"

namespace weft {

struct CollisionResponseStats {
  int proximity_contacts = 0;
  int ccd_passes = 0;
  int ccd_impulses = 0;
  ImpactZoneResult impact_zones;
};

CollisionResponseStats respond_to_collisions(CollisionStep& step,
                                             const std::vector<VertexFacePair>& vertex_faces,
                                             const std::vector<EdgeEdgePair>& edge_edges,
                                             const ResponseSettings& settings, ImpactZoneWorkspace& workspace,
                                             std::vector<ContactRecord>* records);

}  // namespace weft
