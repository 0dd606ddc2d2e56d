#pragma once
// Closest points between two segments, robust for parallel and zero-length edges.
#include "core/math.hpp"

namespace weft {

struct EdgeEdgeClosest {
  Vec3 point_a;     // a0 + s (a1 - a0)
  Vec3 point_b;     // b0 + t (b1 - b0)
  double s;         // in [0, 1]
  double t;         // in [0, 1]
  double distance;  // |point_a - point_b|
};

// Closest points of segments (a0, a1) and (b0, b1). Parallel segments get one of their closest
// pairs (an endpoint of one of them); a zero-length segment acts as a point.
EdgeEdgeClosest edge_edge_closest(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

// From a point of segment (a0, a1) to a point of segment (b0, b1): the closest pair, from the
// normal equations with each parameter clamped in turn (no endpoint search, no square root).
// Exact where edge_edge_closest's interior case is; for near-parallel segments it may join a
// pair that is not the closest. The candidate filter's cheap axis.
Vec3 edge_edge_offset(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace weft
