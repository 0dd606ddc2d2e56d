#pragma once
// Proximity response (BFA 2002 section 7.2): for candidate pairs closer than the thickness at the
// start of the step, an inelastic impulse cancels their approach, a spring-like repulsion impulse
// pushes them back towards the thickness, and Coulomb friction acts on their relative tangential
// velocity. Impulses are applied pair by pair (Gauss-Seidel), each seeing the previous ones.
#include <vector>

#include "collision/collision_step.hpp"
#include "collision/contact_pairs.hpp"
#include "collision/contact_record.hpp"

namespace weft {

// Applies the proximity impulses to step.x_end and step.velocity and appends one record per pair
// acted on to `records` (when not null). Pairs that share a vertex, or whose vertices all have
// infinite mass, are skipped. Returns the number of pairs acted on.
int apply_proximity_response(CollisionStep& step, PairRange<VertexFacePair> vertex_faces,
                             PairRange<EdgeEdgePair> edge_edges, const ResponseSettings& settings,
                             std::vector<ContactRecord>* records);

}  // namespace weft
