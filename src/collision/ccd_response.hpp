#pragma once
// Continuous collision response (BFA 2002 section 7.3): every candidate pair is tested over the
// motion x_start -> x_end; a pair that collides gets an inelastic impulse that stops its approach
// along the collision normal (restoring a small gap if the pair started closer than it), applied
// at once so later pairs see the corrected motion. Passes repeat until one finds no collision or
// the pass limit is reached; what remains is left to impact zones.
#include <initializer_list>
#include <optional>
#include <vector>

#include "collision/collision_step.hpp"
#include "collision/contact_impulse.hpp"
#include "collision/contact_pairs.hpp"
#include "collision/contact_record.hpp"

namespace weft {

struct CcdCollision {
  ContactKind kind;
  int primitive_a;         // vertex or edge_a
  int primitive_b;         // triangle or edge_b
  double time;             // fraction of the step
  double distance;         // at `time`
  ContactStencil stencil;  // weights at `time`, normal from primitive b towards primitive a
};

// Whether the boxes swept by two sets of vertices from x0 to x1 come within `gap` of each other
// along every coordinate axis: primitives whose swept boxes stay apart cannot meet, and most
// candidates end here. With x0 = x1, the boxes at one time.
bool swept_boxes_overlap(const Positions& x0, const Positions& x1, std::initializer_list<int> first,
                         std::initializer_list<int> second, double gap);

// Continuous test of one pair over the step's current motion; pairs that share a vertex never
// collide.
std::optional<CcdCollision> detect_collision(const CollisionStep& step, const VertexFacePair& pair,
                                             const ResponseSettings& settings);
std::optional<CcdCollision> detect_collision(const CollisionStep& step, const EdgeEdgePair& pair,
                                             const ResponseSettings& settings);

// Every colliding pair of the current motion, found over the OpenMP threads into per-thread
// buffers that are kept from call to call (so a warmed-up step allocates nothing).
struct CcdCollisions {
  std::vector<CcdCollision> found;                     // in pair order, whatever the thread count
  std::vector<std::vector<CcdCollision>> chunk_found;  // scratch, one per chunk of the pairs

  bool empty() const { return found.empty(); }
};

// The most chunks detect_collisions cuts the pairs into (at least 256 pairs a chunk).
constexpr int detection_chunks = 32;

// Clears `collisions` and fills it with every colliding pair of the current motion.
void detect_collisions(const CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                       const std::vector<EdgeEdgePair>& edge_edges, const ResponseSettings& settings,
                       CcdCollisions& collisions);

// Inelastic impulse on one collision (a no-op where the pair already separates fast enough or all
// its vertices have infinite mass); returns the impulse magnitude.
double apply_ccd_impulse(CollisionStep& step, const CcdCollision& collision,
                         const ResponseSettings& settings);

// The record of a collision before its impulse: the stencil's positive side at the time of
// contact, the depth below the thickness, the given impulse (partners: cloth_cloth until the
// caller labels them).
ContactRecord ccd_contact_record(const CollisionStep& step, const CcdCollision& collision, double impulse,
                                 const ResponseSettings& settings);

struct CcdResponseResult {
  int passes = 0;      // detection passes run
  int impulses = 0;    // collisions acted on, over all passes
  bool clean = false;  // the last pass found no collision
};

// Up to settings.max_ccd_passes passes of detection and impulses; appends a record per impulse.
CcdResponseResult apply_ccd_response(CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                                     const std::vector<EdgeEdgePair>& edge_edges,
                                     const ResponseSettings& settings, std::vector<ContactRecord>* records);

}  // namespace weft
