// The candidate lists' bookkeeping: combined index offsets, the radix sort with deduplication
// and the merge of new pairs. What the broad phase writes into them is tested in
// test_primitive_queries.cpp.
#include "collision/candidates.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <vector>

namespace weft {
namespace {

TEST(Candidates, OffsetsAreTheRunningTotalsOfTheMeshesBefore) {
  const MeshIndexOffsets first{};
  const MeshIndexOffsets second = next_offsets(first, 30, 40, 69);
  EXPECT_EQ(second.vertex, 30);
  EXPECT_EQ(second.triangle, 40);
  EXPECT_EQ(second.edge, 69);
  const MeshIndexOffsets third = next_offsets(second, 5, 6, 7);
  EXPECT_EQ(third.vertex, 35);
  EXPECT_EQ(third.triangle, 46);
  EXPECT_EQ(third.edge, 76);
}

TEST(Candidates, SortCandidatesOrdersAndDeduplicatesLikeStdSort) {
  std::mt19937 rng(13);
  for (const int largest : {50, 70000, 2147483647}) {
    std::uniform_int_distribution<int> index(0, largest);
    CollisionCandidates candidates;
    for (int k = 0; k < 20000; ++k) {
      candidates.vertex_face.push_back({index(rng), index(rng)});
      candidates.edge_edge.push_back({index(rng), index(rng)});
      if (k % 3 == 0) candidates.edge_edge.push_back(candidates.edge_edge.back());  // repeats
    }
    std::vector<VertexFacePair> vertex_face = candidates.vertex_face;
    std::vector<EdgeEdgePair> edge_edge = candidates.edge_edge;
    std::sort(vertex_face.begin(), vertex_face.end());
    vertex_face.erase(std::unique(vertex_face.begin(), vertex_face.end()), vertex_face.end());
    std::sort(edge_edge.begin(), edge_edge.end());
    edge_edge.erase(std::unique(edge_edge.begin(), edge_edge.end()), edge_edge.end());
    sort_candidates(candidates);
    EXPECT_TRUE(candidates.vertex_face == vertex_face) << largest;
    EXPECT_TRUE(candidates.edge_edge == edge_edge) << largest;
    EXPECT_LT(edge_edge.size(), 26667u);  // the repeats were there to remove
  }
}

TEST(Candidates, MergeNewCandidatesKeepsTheNewPairsAndTheSortedUnion) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> index(0, 400);
  for (int round = 0; round < 20; ++round) {
    CollisionCandidates all, added;
    for (int k = 0; k < 3000; ++k) {
      all.vertex_face.push_back({index(rng), index(rng)});
      all.edge_edge.push_back({index(rng), index(rng)});
    }
    for (int k = 0; k < 1000 * (round % 3); ++k) {
      added.vertex_face.push_back({index(rng), index(rng)});
      added.edge_edge.push_back({index(rng), index(rng)});
    }
    sort_candidates(all);
    sort_candidates(added);
    std::vector<VertexFacePair> union_vf, new_vf;
    std::set_union(all.vertex_face.begin(), all.vertex_face.end(), added.vertex_face.begin(),
                   added.vertex_face.end(), std::back_inserter(union_vf));
    std::set_difference(added.vertex_face.begin(), added.vertex_face.end(), all.vertex_face.begin(),
                        all.vertex_face.end(), std::back_inserter(new_vf));
    std::vector<EdgeEdgePair> union_ee, new_ee;
    std::set_union(all.edge_edge.begin(), all.edge_edge.end(), added.edge_edge.begin(), added.edge_edge.end(),
                   std::back_inserter(union_ee));
    std::set_difference(added.edge_edge.begin(), added.edge_edge.end(), all.edge_edge.begin(),
                        all.edge_edge.end(), std::back_inserter(new_ee));
    if (round % 3 != 0) {
      EXPECT_FALSE(new_vf.empty());
      EXPECT_LT(new_vf.size(), added.vertex_face.size()) << "some pairs were there already";
    }
    merge_new_candidates(all, added);
    EXPECT_TRUE(all.vertex_face == union_vf) << round;
    EXPECT_TRUE(all.edge_edge == union_ee) << round;
    EXPECT_TRUE(added.vertex_face == new_vf) << round;
    EXPECT_TRUE(added.edge_edge == new_ee) << round;
  }
}

}  // namespace
}  // namespace weft
