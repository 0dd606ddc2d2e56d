#pragma once
// Continuous vertex-face collision over one step with linear motion (BFA 2002 section 6): the
// earliest time at which the vertex and the triangle are coplanar and the vertex lies within eta
// of the triangle. Either side of the triangle counts.
#include <optional>

#include "core/math.hpp"

namespace weft {

struct VertexFaceImpact {
  double time;       // fraction of the step in [0, 1]
  Vec3 barycentric;  // weights of the triangle's vertices at the closest point at `time`
  Vec3 normal;       // unit; points from the triangle towards the side the vertex comes from
  double distance;   // vertex-triangle distance at `time` (<= eta, or slightly more where the search
                     // gave up conservatively)
};

// p moves from p_start to p_end, the triangle (a, b, c) from *_start to *_end. `eta` is the
// proximity tolerance applied at coplanar times (a length, > 0).
std::optional<VertexFaceImpact> vertex_face_ccd(const Vec3& p_start, const Vec3& a_start, const Vec3& b_start,
                                                const Vec3& c_start, const Vec3& p_end, const Vec3& a_end,
                                                const Vec3& b_end, const Vec3& c_end, double eta);

}  // namespace weft
