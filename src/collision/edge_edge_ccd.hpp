#pragma once
// Continuous edge-edge collision over one step with linear motion (BFA 2002 section 6): the
// earliest time at which the two edges are coplanar and within eta of each other.
#include <optional>

#include "core/math.hpp"

namespace weft {

struct EdgeEdgeImpact {
  double time;      // fraction of the step in [0, 1]
  double s;         // closest point a0 + s (a1 - a0) at `time`
  double t;         // closest point b0 + t (b1 - b0) at `time`
  Vec3 normal;      // unit; points from edge b towards the side edge a comes from
  double distance;  // edge-edge distance at `time`
};

// Edge a = (a0, a1) and edge b = (b0, b1) move linearly from *_start to *_end; `eta` is the
// proximity tolerance applied at coplanar times (a length, > 0).
std::optional<EdgeEdgeImpact> edge_edge_ccd(const Vec3& a0_start, const Vec3& a1_start, const Vec3& b0_start,
                                            const Vec3& b1_start, const Vec3& a0_end, const Vec3& a1_end,
                                            const Vec3& b0_end, const Vec3& b1_end, double eta);

}  // namespace weft
