#pragma once
// The pairs of overlapping boxes among many (the candidates of the exact checks): a bounding-
// volume hierarchy over the boxes, built by median splits and traversed against itself. The
// check's own, apart from the collision code's BVH, so that the two share no filter.
#include <utility>
#include <vector>

#include "core/math.hpp"

namespace weft {

struct CheckBox {
  Vec3 lower;
  Vec3 upper;
  bool obstacle = false;  // pairs of two obstacle boxes are not reported
};

// Every pair (i, j), i < j, of closed boxes that overlap, except pairs of two obstacles; in no
// particular order.
std::vector<std::pair<int, int>> overlapping_box_pairs(const std::vector<CheckBox>& boxes);

}  // namespace weft
