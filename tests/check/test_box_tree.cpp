// The box tree's pairs against testing every pair, on random boxes with obstacles among them.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "check/box_tree.hpp"

namespace weft {
namespace {

TEST(BoxTree, FindsExactlyTheOverlappingPairsOfNonObstacles) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> where(0.0, 1.0), size(0.0, 0.08);
  for (const int count : {0, 1, 5, 300}) {
    std::vector<CheckBox> boxes;
    for (int i = 0; i < count; ++i) {
      const Vec3 lower(where(random), where(random), where(random));
      boxes.push_back({lower, lower + Vec3(size(random), size(random), size(random)), i % 3 == 0});
    }
    // Two boxes touching at a face overlap (closed boxes).
    if (count > 1) {
      boxes[1].lower = Vec3(boxes[0].upper.x(), boxes[0].lower.y(), boxes[0].lower.z());
      boxes[1].upper = boxes[1].lower + Vec3(0.01, 0.01, 0.01);
    }
    std::vector<std::pair<int, int>> expected;
    for (int i = 0; i < count; ++i) {
      for (int j = i + 1; j < count; ++j) {
        const bool apart = (boxes[i].upper.array() < boxes[j].lower.array()).any() ||
                           (boxes[j].upper.array() < boxes[i].lower.array()).any();
        if (!apart && !(boxes[i].obstacle && boxes[j].obstacle)) expected.emplace_back(i, j);
      }
    }
    std::vector<std::pair<int, int>> found = overlapping_box_pairs(boxes);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << count << " boxes";
    if (count > 1) {
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), std::make_pair(0, 1)));
    }
  }
}

}  // namespace
}  // namespace weft
