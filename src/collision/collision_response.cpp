#include "collision/collision_response.hpp"

#include "collision/proximity_response.hpp"

namespace weft {

CollisionResponseStats respond_to_collisions(CollisionStep& step,
                                             const std::vector<VertexFacePair>& vertex_faces,
                                             const std::vector<EdgeEdgePair>& edge_edges,
                                             const ResponseSettings& settings, ImpactZoneWorkspace& workspace,
                                             std::vector<ContactRecord>* records) {
  CollisionResponseStats stats;
  stats.proximity_contacts = apply_proximity_response(step, vertex_faces, edge_edges, settings, records);
  const CcdResponseResult ccd = apply_ccd_response(step, vertex_faces, edge_edges, settings, records);
  stats.ccd_passes = ccd.passes;
  stats.ccd_impulses = ccd.impulses;
  // A clean last CCD pass leaves nothing for the zones: skip their extra detection pass.
  if (ccd.clean) {
    stats.impact_zones.clean = true;
  } else {
    stats.impact_zones = resolve_impact_zones(step, vertex_faces, edge_edges, settings, workspace);
  }
  return stats;
}

}  // namespace weft
