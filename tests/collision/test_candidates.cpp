// Narrow-phase candidates from triangle pairs: hand-counted small cases, and on grids the
// vertex-face and edge-edge sets equal a reference written with std::set and edge lookup by
// vertex pair; combined index spaces for pairs between meshes.
#include "collision/candidates.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

template <typename T>
bool sorted_and_unique(const std::vector<T>& items) {
  return std::adjacent_find(items.begin(), items.end(), [](const T& x, const T& y) { return !(x < y); }) ==
         items.end();
}

// Reference: edges looked up by their vertex pair, candidates collected in sets.
struct ReferenceMesh {
  const Triangles* triangles;
  std::map<std::pair<int, int>, int> edge_of_vertices;
  MeshIndexOffsets offsets;
};

ReferenceMesh reference_mesh(const Triangles& triangles, const MeshTopology& topology,
                             MeshIndexOffsets offsets) {
  ReferenceMesh mesh{&triangles, {}, offsets};
  for (int e = 0; e < topology.num_edges(); ++e) {
    mesh.edge_of_vertices[{topology.edges(0, e), topology.edges(1, e)}] = e;
  }
  return mesh;
}

struct ReferenceCandidates {
  std::set<std::pair<int, int>> vertex_face;
  std::set<std::pair<int, int>> edge_edge;
};

void add_reference(const std::vector<TrianglePair>& pairs, const ReferenceMesh& first,
                   const ReferenceMesh& second, bool same_mesh, ReferenceCandidates& out) {
  for (const TrianglePair& pair : pairs) {
    const Vec3i s = first.triangles->col(pair.a);
    const Vec3i t = second.triangles->col(pair.b);
    const auto corner_of = [](const Vec3i& tri, int v) { return tri[0] == v || tri[1] == v || tri[2] == v; };
    for (int k = 0; k < 3; ++k) {
      if (!same_mesh || !corner_of(t, s[k]))
        out.vertex_face.insert({first.offsets.vertex + s[k], second.offsets.triangle + pair.b});
      if (!same_mesh || !corner_of(s, t[k]))
        out.vertex_face.insert({second.offsets.vertex + t[k], first.offsets.triangle + pair.a});
    }
    for (int i = 0; i < 3; ++i) {
      const int s0 = std::min(s[i], s[(i + 1) % 3]), s1 = std::max(s[i], s[(i + 1) % 3]);
      for (int j = 0; j < 3; ++j) {
        const int t0 = std::min(t[j], t[(j + 1) % 3]), t1 = std::max(t[j], t[(j + 1) % 3]);
        if (same_mesh && (s0 == t0 || s0 == t1 || s1 == t0 || s1 == t1)) continue;
        const int a = first.offsets.edge + first.edge_of_vertices.at({s0, s1});
        const int b = second.offsets.edge + second.edge_of_vertices.at({t0, t1});
        out.edge_edge.insert({std::min(a, b), std::max(a, b)});
      }
    }
  }
}

void expect_equal(const CollisionCandidates& candidates, const ReferenceCandidates& reference) {
  EXPECT_TRUE(sorted_and_unique(candidates.vertex_face));
  EXPECT_TRUE(sorted_and_unique(candidates.edge_edge));
  using PairList = std::vector<std::pair<int, int>>;
  PairList vertex_face, edge_edge;
  for (const VertexFacePair& p : candidates.vertex_face) vertex_face.push_back({p.vertex, p.triangle});
  for (const EdgeEdgePair& p : candidates.edge_edge) edge_edge.push_back({p.edge_a, p.edge_b});
  EXPECT_EQ(vertex_face, PairList(reference.vertex_face.begin(), reference.vertex_face.end()));
  EXPECT_EQ(edge_edge, PairList(reference.edge_edge.begin(), reference.edge_edge.end()));
}

TEST(Candidates, TwoSeparateTrianglesGiveSixVertexFaceAndNineEdgeEdgePairs) {
  Triangles triangles(3, 2);
  triangles << 0, 3, 1, 4, 2, 5;
  const MeshTopology topology = build_topology(triangles, 6);
  CollisionCandidates candidates;
  add_self_candidates({{0, 1}}, {triangles, topology, {}}, candidates);
  const std::vector<VertexFacePair> expected_vertex_face = {{0, 1}, {1, 1}, {2, 1}, {3, 0}, {4, 0}, {5, 0}};
  EXPECT_EQ(candidates.vertex_face, expected_vertex_face);
  ASSERT_EQ(candidates.edge_edge.size(), 9u);
  for (const EdgeEdgePair& pair : candidates.edge_edge) {
    // Edges sorted by vertex pair: 0-1, 0-2, 1-2 belong to triangle 0, 3-4, 3-5, 4-5 to triangle 1.
    EXPECT_LT(pair.edge_a, 3);
    EXPECT_GE(pair.edge_b, 3);
  }
}

TEST(Candidates, SharedVertexIsSkipped) {
  // (0, 1, 2) and (0, 3, 4) share vertex 0.
  Triangles triangles(3, 2);
  triangles << 0, 0, 1, 3, 2, 4;
  const MeshTopology topology = build_topology(triangles, 5);
  CollisionCandidates candidates;
  add_self_candidates({{0, 1}}, {triangles, topology, {}}, candidates);
  const std::vector<VertexFacePair> expected_vertex_face = {{1, 1}, {2, 1}, {3, 0}, {4, 0}};
  EXPECT_EQ(candidates.vertex_face, expected_vertex_face);
  // Of the 9 edge pairs, the 4 between edges through vertex 0 are dropped.
  EXPECT_EQ(candidates.edge_edge.size(), 5u);
  for (const EdgeEdgePair& pair : candidates.edge_edge) {
    const int a0 = topology.edges(0, pair.edge_a), a1 = topology.edges(1, pair.edge_a);
    const int b0 = topology.edges(0, pair.edge_b), b1 = topology.edges(1, pair.edge_b);
    EXPECT_TRUE(a0 != b0 && a0 != b1 && a1 != b0 && a1 != b1);
  }
}

TEST(Candidates, AHingeFoldedFlatNeedsTheNeighbourPair) {
  // Triangles (0, 1, 2) and (1, 0, 3) share the edge 0-1; vertex 3 is folded over onto the
  // first triangle, 1e-3 above it.
  Positions x(3, 4);
  x << 0.0, 1.0, 0.3, 0.3,  //
      0.0, 0.0, 1.0, 0.5,   //
      0.0, 0.0, 0.0, 1e-3;
  Triangles triangles(3, 2);
  triangles << 0, 1, 1, 0, 2, 3;
  const MeshTopology topology = build_topology(triangles, 4);
  Bvh bvh;
  bvh.build(x, triangles, 0.01);
  const VertexFacePair folded{3, 0};

  CollisionCandidates skipping;
  add_self_candidates(find_self_pairs(bvh), {triangles, topology, {}}, skipping);
  EXPECT_TRUE(skipping.vertex_face.empty()) << "the only pair shares a vertex and is skipped";

  CollisionCandidates keeping;
  add_self_candidates(find_self_pairs(bvh, SharedVertexPairs::keep), {triangles, topology, {}}, keeping);
  EXPECT_EQ(keeping.vertex_face, (std::vector<VertexFacePair>{{2, 1}, folded}));
  // Sides 1-2 and 0-3, and 2-0 and 3-1, each touch the shared edge but not each other: a fold
  // past flat can cross them, so both pairs are candidates.
  const auto edge = [&](int v0, int v1) {
    for (int e = 0; e < topology.num_edges(); ++e) {
      if (topology.edges(0, e) == std::min(v0, v1) && topology.edges(1, e) == std::max(v0, v1)) return e;
    }
    return -1;
  };
  std::vector<EdgeEdgePair> expected = {{std::min(edge(1, 2), edge(0, 3)), std::max(edge(1, 2), edge(0, 3))},
                                        {std::min(edge(2, 0), edge(3, 1)), std::max(edge(2, 0), edge(3, 1))}};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(keeping.edge_edge, expected);
}

TEST(Candidates, SelfCandidatesOnAGridMatchTheReference) {
  const TriangleMesh grid = make_grid(12, 9, 1.0, 1.0, GridTriangulation::alternating);
  const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
  // Every pair of distinct triangles, adjacent ones included: the candidate stage must skip
  // shared corners itself.
  std::vector<TrianglePair> pairs;
  for (int s = 0; s < grid.num_triangles(); ++s) {
    for (int t = s + 1; t < grid.num_triangles(); t += 3) pairs.push_back({s, t});
  }
  CollisionCandidates candidates;
  add_self_candidates(pairs, {grid.triangles, topology, {}}, candidates);
  ReferenceCandidates reference;
  add_reference(pairs, reference_mesh(grid.triangles, topology, {}),
                reference_mesh(grid.triangles, topology, {}), true, reference);
  EXPECT_GT(reference.vertex_face.size(), 1000u);
  expect_equal(candidates, reference);
  for (const VertexFacePair& pair : candidates.vertex_face) {
    const Vec3i corners = grid.triangles.col(pair.triangle);
    EXPECT_TRUE(corners[0] != pair.vertex && corners[1] != pair.vertex && corners[2] != pair.vertex);
  }

  // Adding the same pairs again changes nothing.
  const CollisionCandidates before = candidates;
  add_self_candidates(pairs, {grid.triangles, topology, {}}, candidates);
  EXPECT_EQ(candidates.vertex_face, before.vertex_face);
  EXPECT_EQ(candidates.edge_edge, before.edge_edge);
}

TEST(Candidates, PairsFromTheBvhOfACrumpledGrid) {
  TriangleMesh grid = make_grid(20, 20, 1.0, 1.0, GridTriangulation::regular);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> noise(-0.04, 0.04);
  for (int v = 0; v < grid.num_vertices(); ++v) {
    grid.positions(2, v) = 0.2 * std::sin(12.0 * grid.positions(0, v)) + noise(rng);
    grid.positions(0, v) *= 0.5;
  }
  const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.01);
  const std::vector<TrianglePair> pairs = find_self_pairs(bvh);
  ASSERT_FALSE(pairs.empty());
  CollisionCandidates candidates;
  add_self_candidates(pairs, {grid.triangles, topology, {}}, candidates);
  ReferenceCandidates reference;
  const ReferenceMesh mesh = reference_mesh(grid.triangles, topology, {});
  add_reference(pairs, mesh, mesh, true, reference);
  expect_equal(candidates, reference);
  // Pairs share no vertex, so each gives all 6 vertex-face pairs before deduplication.
  EXPECT_LE(candidates.vertex_face.size(), 6 * pairs.size());
  EXPECT_LT(candidates.edge_edge.size(), 9 * pairs.size()) << "edges shared by neighbours are deduplicated";
}

TEST(Candidates, AppendsAreTheSameOnAnyThreadCount) {
  // Enough pairs for the appends to split them over threads: the unsorted lists must come out
  // in the same order on 1, 2 and 3 threads, and sorted they must match the reference.
  TriangleMesh grid = make_grid(60, 60, 1.0, 1.0, GridTriangulation::regular);
  for (int v = 0; v < grid.num_vertices(); ++v) grid.positions(2, v) = 0.1 * std::sin(20.0 * grid.positions(0, v));
  const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.03);
  const std::vector<TrianglePair> pairs = find_self_pairs(bvh);
  ASSERT_GT(pairs.size(), 5000u);
  const int threads_before = omp_get_max_threads();
  std::vector<CollisionCandidates> results;
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    CollisionCandidates candidates;
    append_self_candidates(pairs, {grid.triangles, topology, {}}, candidates);
    append_self_candidates(pairs, {grid.triangles, topology, {}}, candidates);  // buffers reused
    results.push_back(candidates);
  }
  omp_set_num_threads(threads_before);
  for (int k = 1; k < 3; ++k) {
    EXPECT_TRUE(results[k].vertex_face == results[0].vertex_face) << k + 1 << " threads";
    EXPECT_TRUE(results[k].edge_edge == results[0].edge_edge) << k + 1 << " threads";
  }
  sort_candidates(results[2]);
  ReferenceCandidates reference;
  const ReferenceMesh mesh = reference_mesh(grid.triangles, topology, {});
  add_reference(pairs, mesh, mesh, true, reference);
  expect_equal(results[2], reference);
}

TEST(Candidates, BetweenMeshesUseCombinedIndices) {
  const TriangleMesh cloth = make_grid(6, 5, 1.0, 1.0, GridTriangulation::regular);
  TriangleMesh obstacle = make_grid(4, 4, 1.0, 1.0, GridTriangulation::cross);
  const MeshTopology cloth_topology = build_topology(cloth.triangles, cloth.num_vertices());
  const MeshTopology obstacle_topology = build_topology(obstacle.triangles, obstacle.num_vertices());
  const MeshIndexOffsets cloth_offsets{};
  const MeshIndexOffsets obstacle_offsets =
      next_offsets(cloth_offsets, cloth.num_vertices(), cloth.num_triangles(), cloth_topology.num_edges());
  EXPECT_EQ(obstacle_offsets.vertex, 30);
  EXPECT_EQ(obstacle_offsets.triangle, cloth.num_triangles());
  EXPECT_EQ(obstacle_offsets.edge, cloth_topology.num_edges());

  // Both grids lie in the same plane, so every pair of triangles overlaps.
  Bvh a, b;
  a.build(cloth.positions, cloth.triangles, 0.0);
  b.build(obstacle.positions, obstacle.triangles, 0.0);
  const std::vector<TrianglePair> pairs = find_pairs_between(a, b);
  ASSERT_FALSE(pairs.empty());
  const CandidateMesh first{cloth.triangles, cloth_topology, cloth_offsets};
  const CandidateMesh second{obstacle.triangles, obstacle_topology, obstacle_offsets};
  CollisionCandidates candidates;
  add_candidates_between(pairs, first, second, candidates);
  ReferenceCandidates reference;
  add_reference(pairs, reference_mesh(cloth.triangles, cloth_topology, cloth_offsets),
                reference_mesh(obstacle.triangles, obstacle_topology, obstacle_offsets), false, reference);
  expect_equal(candidates, reference);
  for (const EdgeEdgePair& pair : candidates.edge_edge) {
    EXPECT_LT(pair.edge_a, obstacle_offsets.edge);
    EXPECT_GE(pair.edge_b, obstacle_offsets.edge);
  }

  // Self candidates of both meshes join the same sorted list.
  const std::size_t between_count = candidates.vertex_face.size();
  add_self_candidates(find_self_pairs(a), first, candidates);
  add_self_candidates(find_self_pairs(b), second, candidates);
  const ReferenceMesh cloth_reference = reference_mesh(cloth.triangles, cloth_topology, cloth_offsets);
  const ReferenceMesh obstacle_reference =
      reference_mesh(obstacle.triangles, obstacle_topology, obstacle_offsets);
  add_reference(find_self_pairs(a), cloth_reference, cloth_reference, true, reference);
  add_reference(find_self_pairs(b), obstacle_reference, obstacle_reference, true, reference);
  EXPECT_GT(candidates.vertex_face.size(), between_count);
  expect_equal(candidates, reference);
}

}  // namespace
}  // namespace weft

namespace weft {
namespace {

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

namespace weft {
namespace {

// A crumpled grid moving over a step, its vertices at `offset` in the combined index space.
struct SweptGrid {
  TriangleMesh mesh;
  Positions x_start, x_end;
  MeshTopology topology;
  Bvh bvh;
};

SweptGrid swept_grid(int n, unsigned seed, const Vec3& shift, double gap) {
  SweptGrid grid;
  grid.mesh = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.03, 0.03);
  grid.x_start = grid.mesh.positions;
  for (int v = 0; v < grid.mesh.num_vertices(); ++v) {
    grid.x_start(2, v) = 0.15 * std::sin(9.0 * grid.x_start(0, v)) + noise(rng);
    grid.x_start.col(v) += shift;
  }
  grid.x_end = grid.x_start;
  for (int v = 0; v < grid.mesh.num_vertices(); ++v) grid.x_end.col(v) += Vec3(noise(rng), noise(rng), noise(rng));
  grid.topology = build_topology(grid.mesh.triangles, grid.mesh.num_vertices());
  grid.bvh.build(grid.x_start, grid.x_end, grid.mesh.triangles, 0.5 * gap);  // as the collision phase
  return grid;
}

struct TwoSweptGrids {
  static constexpr double gap = 0.02;
  SweptGrid a, b;
  Positions lower, upper;  // combined vertex boxes: a's vertices, then b's
  MeshIndexOffsets offsets_b;

  TwoSweptGrids() : TwoSweptGrids(swept_grid(24, 3, Vec3::Zero(), gap), swept_grid(16, 4, Vec3(0.2, 0.3, 0.05), gap)) {}
  TwoSweptGrids(SweptGrid first, SweptGrid second) : a(std::move(first)), b(std::move(second)) {
    const int na = a.mesh.num_vertices(), nb = b.mesh.num_vertices();
    lower.resize(3, na + nb);
    upper.resize(3, na + nb);
    lower << a.x_start.cwiseMin(a.x_end), b.x_start.cwiseMin(b.x_end);
    upper << a.x_start.cwiseMax(a.x_end), b.x_start.cwiseMax(b.x_end);
    offsets_b = next_offsets({}, na, a.mesh.num_triangles(), a.topology.num_edges());
  }
};

// Grid a against itself and against grid b, as the collision phase's full query.
CollisionCandidates full_query(const TwoSweptGrids& grids, TrianglePairList list) {
  const SweptVertexBoxes boxes{grids.lower, grids.upper, grids.gap};
  const CandidateMesh mesh_a{grids.a.mesh.triangles, grids.a.topology, {}, &boxes};
  const CandidateMesh mesh_b{grids.b.mesh.triangles, grids.b.topology, grids.offsets_b, &boxes};
  CollisionCandidates candidates;
  append_self_candidates(find_self_pairs(grids.a.bvh, SharedVertexPairs::keep), mesh_a, candidates, list);
  append_candidates_between(find_pairs_between(grids.a.bvh, grids.b.bvh), mesh_a, mesh_b, candidates, list);
  sort_candidates(candidates);
  return candidates;
}

template <typename T>
std::vector<T> sorted_copy(std::vector<T> items) {
  std::sort(items.begin(), items.end());
  return items;
}

template <typename T>
bool has_repeats(const std::vector<T>& items) {
  const std::vector<T> sorted = sorted_copy(items);
  return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

TEST(Candidates, CompleteListsWriteEachPrimitivePairOnceAndTheSameSet) {
  const TwoSweptGrids grids;
  const SweptVertexBoxes boxes{grids.lower, grids.upper, grids.gap};
  const CandidateMesh mesh_a{grids.a.mesh.triangles, grids.a.topology, {}, &boxes};
  const CandidateMesh mesh_b{grids.b.mesh.triangles, grids.b.topology, grids.offsets_b, &boxes};
  const std::vector<TrianglePair> self_pairs = find_self_pairs(grids.a.bvh, SharedVertexPairs::keep);
  const std::vector<TrianglePair> between_pairs = find_pairs_between(grids.a.bvh, grids.b.bvh);
  ASSERT_GT(self_pairs.size(), 500u);
  ASSERT_GT(between_pairs.size(), 500u);

  for (const bool self : {true, false}) {
    CollisionCandidates every, once;
    if (self) {
      append_self_candidates(self_pairs, mesh_a, every, TrianglePairList::any);
      append_self_candidates(self_pairs, mesh_a, once, TrianglePairList::complete);
    } else {
      append_candidates_between(between_pairs, mesh_a, mesh_b, every, TrianglePairList::any);
      append_candidates_between(between_pairs, mesh_a, mesh_b, once, TrianglePairList::complete);
    }
    EXPECT_FALSE(has_repeats(once.vertex_face)) << self;
    EXPECT_FALSE(has_repeats(once.edge_edge)) << self;
    EXPECT_TRUE(has_repeats(every.vertex_face)) << self;
    EXPECT_LT(2 * once.vertex_face.size(), every.vertex_face.size()) << self;
    EXPECT_LT(2 * once.edge_edge.size(), every.edge_edge.size()) << self;
    sort_candidates(every);
    EXPECT_GT(every.vertex_face.size(), 500u) << self;
    EXPECT_GT(every.edge_edge.size(), 500u) << self;
    EXPECT_TRUE(sorted_copy(once.vertex_face) == every.vertex_face) << self;
    EXPECT_TRUE(sorted_copy(once.edge_edge) == every.edge_edge) << self;
  }
}

TEST(Candidates, ReQueryOfListedTrianglesFindsEveryPairOfTheirVertices) {
  // The collision phase's re-query: the triangles around some vertices against every mesh, with
  // complete lists, must give every candidate of the full query that involves those vertices.
  const TwoSweptGrids grids;
  const SweptVertexBoxes boxes{grids.lower, grids.upper, grids.gap};
  const CandidateMesh mesh_a{grids.a.mesh.triangles, grids.a.topology, {}, &boxes};
  const CandidateMesh mesh_b{grids.b.mesh.triangles, grids.b.topology, grids.offsets_b, &boxes};
  const CollisionCandidates full = full_query(grids, TrianglePairList::any);

  std::vector<char> chosen(grids.a.mesh.num_vertices(), 0);
  for (int v = 0; v < grids.a.mesh.num_vertices(); v += 7) chosen[v] = 1;
  std::vector<int> listed;
  for (int t = 0; t < grids.a.mesh.num_triangles(); ++t) {
    const Vec3i corners = grids.a.mesh.triangles.col(t);
    if (chosen[corners[0]] || chosen[corners[1]] || chosen[corners[2]]) listed.push_back(t);
  }
  std::vector<TrianglePair> pairs;
  std::vector<int> scratch;
  CollisionCandidates requery;
  find_pairs_of(grids.a.bvh, listed, grids.a.bvh, true, pairs, scratch, SharedVertexPairs::keep);
  append_self_candidates(pairs, mesh_a, requery, TrianglePairList::complete);
  find_pairs_of(grids.a.bvh, listed, grids.b.bvh, false, pairs, scratch);
  append_candidates_between(pairs, mesh_a, mesh_b, requery, TrianglePairList::complete);
  sort_candidates(requery);

  const auto is_chosen = [&](int v) { return v < grids.offsets_b.vertex && chosen[v]; };
  const Triangles& tri_a = grids.a.mesh.triangles;
  const auto edge_vertex = [&](int e, int k) {
    return e < grids.offsets_b.edge ? grids.a.topology.edges(k, e) : grids.offsets_b.vertex;  // b: never chosen
  };
  int expected = 0;
  for (const VertexFacePair& pair : full.vertex_face) {
    const bool face_chosen = pair.triangle < grids.offsets_b.triangle &&
                             (is_chosen(tri_a(0, pair.triangle)) || is_chosen(tri_a(1, pair.triangle)) ||
                              is_chosen(tri_a(2, pair.triangle)));
    if (!is_chosen(pair.vertex) && !face_chosen) continue;
    ++expected;
    EXPECT_TRUE(std::binary_search(requery.vertex_face.begin(), requery.vertex_face.end(), pair))
        << pair.vertex << " " << pair.triangle;
  }
  for (const EdgeEdgePair& pair : full.edge_edge) {
    if (!is_chosen(edge_vertex(pair.edge_a, 0)) && !is_chosen(edge_vertex(pair.edge_a, 1)) &&
        !is_chosen(edge_vertex(pair.edge_b, 0)) && !is_chosen(edge_vertex(pair.edge_b, 1))) {
      continue;
    }
    ++expected;
    EXPECT_TRUE(std::binary_search(requery.edge_edge.begin(), requery.edge_edge.end(), pair))
        << pair.edge_a << " " << pair.edge_b;
  }
  EXPECT_GT(expected, 1000);
  EXPECT_LT(requery.vertex_face.size() + requery.edge_edge.size(),
            full.vertex_face.size() + full.edge_edge.size());
}

// Positions drawn inside each vertex's box grown by `slack` per coordinate (corners half the time).
Positions positions_in_boxes(const Positions& lower, const Positions& upper, double slack, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Positions x(3, lower.cols());
  for (Eigen::Index v = 0; v < lower.cols(); ++v) {
    for (int d = 0; d < 3; ++d) {
      const double u = unit(rng) < 0.5 ? unit(rng) : std::round(unit(rng));
      x(d, v) = lower(d, v) - slack + u * (upper(d, v) - lower(d, v) + 2.0 * slack);
    }
  }
  return x;
}

// What CollisionPhase::verify_motion relies on: with every vertex within `slack` (per
// coordinate) of its box, a primitive pair closer than gap - 2 slack is a candidate. Checked by
// brute force on positions drawn in the grown boxes, over every vertex-face pair whose vertex is
// not a corner of the face and every edge-edge pair without a common vertex, within grid a
// (neighbours included) and between the grids. Returns the number of close pairs seen.
int expect_every_close_pair_is_a_candidate(const TwoSweptGrids& grids, unsigned seed) {
  const CollisionCandidates candidates = full_query(grids, TrianglePairList::complete);

  const int na = grids.a.mesh.num_vertices();
  Triangles triangles(3, grids.a.mesh.num_triangles() + grids.b.mesh.num_triangles());
  triangles << grids.a.mesh.triangles, grids.b.mesh.triangles.array() + na;
  Eigen::Matrix2Xi edges(2, grids.a.topology.num_edges() + grids.b.topology.num_edges());
  edges << grids.a.topology.edges, grids.b.topology.edges.array() + na;
  const auto mesh_of = [&](int v) { return v < na ? 0 : 1; };
  std::mt19937 rng(seed);
  int close_pairs = 0;
  for (const double slack : {0.0, 0.3 * grids.gap}) {
    const double within = grids.gap - 2.0 * slack;
    for (int draw = 0; draw < 3; ++draw) {
      const Positions x = positions_in_boxes(grids.lower, grids.upper, slack, rng);
      for (int v = 0; v < x.cols(); ++v) {
        for (int t = 0; t < triangles.cols(); ++t) {
          const Vec3i c = triangles.col(t);
          if (mesh_of(v) == 1 && mesh_of(c[0]) == 1) continue;  // grid b has no self-collision here
          if (c[0] == v || c[1] == v || c[2] == v) continue;
          if (point_triangle_closest(x.col(v), x.col(c[0]), x.col(c[1]), x.col(c[2])).distance >= within) continue;
          ++close_pairs;
          EXPECT_TRUE(std::binary_search(candidates.vertex_face.begin(), candidates.vertex_face.end(),
                                         VertexFacePair{v, t}))
              << v << " " << t << " slack " << slack;
        }
      }
      for (int e = 0; e < edges.cols(); ++e) {
        for (int f = e + 1; f < edges.cols(); ++f) {
          const Eigen::Vector2i a = edges.col(e), b = edges.col(f);
          if (mesh_of(a[0]) == 1 && mesh_of(b[0]) == 1) continue;
          if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
          if (edge_edge_closest(x.col(a[0]), x.col(a[1]), x.col(b[0]), x.col(b[1])).distance >= within) continue;
          ++close_pairs;
          EXPECT_TRUE(std::binary_search(candidates.edge_edge.begin(), candidates.edge_edge.end(),
                                         EdgeEdgePair{e, f}))
              << e << " " << f << " slack " << slack;
        }
      }
    }
  }
  return close_pairs;
}

TEST(Candidates, EveryPairThatComesWithinTheGapInsideItsBoxesIsACandidate) {
  EXPECT_GT(expect_every_close_pair_is_a_candidate(TwoSweptGrids(), 11), 1000);
}

// A grid rolled tightly around the y axis (turns a few gaps apart) whose last rows fold back
// over the roll as a hem, moving a little over the step: pairs between neighbours one or two
// rows apart come within the gap, which a query skipping shared-vertex triangle pairs misses.
SweptGrid rolled_grid_with_hem(int n, unsigned seed, double gap) {
  SweptGrid grid;
  grid.mesh = make_grid(n, 6, 1.0, 0.2, GridTriangulation::alternating);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.1 * gap, 0.1 * gap);
  grid.x_start = grid.mesh.positions;
  const double pitch = 1.5 * gap;  // radial distance between turns
  for (int v = 0; v < grid.mesh.num_vertices(); ++v) {
    const double s = grid.mesh.positions(0, v) + 0.5;  // arc length along the roll, 0 .. 1
    const double y = grid.mesh.positions(1, v);
    if (s < 0.8) {  // Archimedean spiral r = r0 + pitch theta / 2pi, arc length ~ r dtheta
      const double r0 = 0.02;
      double theta = 0.0;
      for (int k = 0; k < 200; ++k) theta += (s / 200.0) / (r0 + pitch * theta / (2.0 * M_PI));
      const double r = r0 + pitch * theta / (2.0 * M_PI);
      grid.x_start.col(v) = Vec3(r * std::cos(theta), y, r * std::sin(theta));
    } else {  // the hem: folded back flat along the first row's tangent, half a gap above it
      grid.x_start.col(v) = Vec3(0.02 + (s - 0.8) * 0.9, y, 0.5 * gap + 0.3 * (s - 0.8) * gap);
    }
    grid.x_start.col(v) += Vec3(noise(rng), noise(rng), noise(rng));
  }
  grid.x_end = grid.x_start;
  for (int v = 0; v < grid.mesh.num_vertices(); ++v) grid.x_end.col(v) += Vec3(noise(rng), noise(rng), noise(rng));
  grid.topology = build_topology(grid.mesh.triangles, grid.mesh.num_vertices());
  grid.bvh.build(grid.x_start, grid.x_end, grid.mesh.triangles, 0.5 * gap);
  return grid;
}

TEST(Candidates, EveryCloseNeighbourPairOfATightRollWithAFoldedHemIsACandidate) {
  const double gap = TwoSweptGrids::gap;
  const TwoSweptGrids grids(rolled_grid_with_hem(60, 21, gap), swept_grid(8, 22, Vec3(0.0, 0.0, 0.3), gap));
  // Neighbour pairs (their triangles share a vertex) within the gap exist, and are candidates.
  const CollisionCandidates candidates = full_query(grids, TrianglePairList::complete);
  const Triangles& own = grids.a.mesh.triangles;
  const MeshTopology& topology = grids.a.topology;
  int neighbour_pairs = 0;
  for (const VertexFacePair& pair : candidates.vertex_face) {
    if (pair.vertex >= grids.offsets_b.vertex || pair.triangle >= grids.offsets_b.triangle) continue;
    bool only_neighbours = true;  // every triangle around the vertex shares a corner with the face
    for (int k = topology.vertex_triangle_start[pair.vertex]; k < topology.vertex_triangle_start[pair.vertex + 1]; ++k) {
      only_neighbours = only_neighbours && share_vertex(own, topology.vertex_triangles[k], pair.triangle);
    }
    neighbour_pairs += only_neighbours;
  }
  EXPECT_GT(neighbour_pairs, 10);
  EXPECT_GT(expect_every_close_pair_is_a_candidate(grids, 23), 1000);
}

TEST(Candidates, AFlatGridAtRestHasNoCandidates) {
  // Every pair of a flat grid that shares no vertex is at least half a cell's diagonal apart, far
  // more than the gap; yet a right triangle's box holds the corner it lacks and a diagonal's box
  // the sides of the next cells, so a coordinate-box filter alone keeps thousands of them.
  const TriangleMesh mesh = make_grid(32, 32, 1.0, 1.0, GridTriangulation::alternating);
  const double gap = 0.005;  // cells of 1/31 m
  const MeshTopology topology = build_topology(mesh.triangles, mesh.num_vertices());
  Bvh bvh;
  bvh.build(mesh.positions, mesh.positions, mesh.triangles, 0.5 * gap);
  const std::vector<TrianglePair> pairs = find_self_pairs(bvh, SharedVertexPairs::keep);
  ASSERT_GT(pairs.size(), 1000u);
  const SweptVertexBoxes boxes{mesh.positions, mesh.positions, gap};
  CollisionCandidates candidates;
  add_self_candidates(pairs, CandidateMesh{mesh.triangles, topology, {}, &boxes}, candidates,
                      TrianglePairList::complete);
  EXPECT_TRUE(candidates.vertex_face.empty()) << candidates.vertex_face.size();
  EXPECT_TRUE(candidates.edge_edge.empty()) << candidates.edge_edge.size();
}

TEST(Candidates, SelfCandidatesOfANonManifoldMeshAreWrittenFromEveryPair) {
  // Three triangles on edge (p, q) and F = (a, b, z): A = (p, q, a) and B = (q, p, b) share a
  // corner with F, only the fin C = (p, q, c) does not, so the edge pair (p, q)-(a, b) comes only
  // from (C, F), a triangle the topology's two-per-edge record does not hold for (p, q).
  enum { p, q, a, b, c, z };
  Positions x(3, 6);
  x << 0.0, 1.0, 0.5, 0.5, 0.5, 0.5,  //
      0.0, 0.0, 0.5, -0.5, 0.0, 0.0,  //
      0.0, 0.0, 0.0, 0.0, 0.5, 0.01;
  Triangles triangles(3, 4);
  triangles << p, q, p, a,  //
      q, p, q, b,           //
      a, b, c, z;
  const MeshTopology topology = build_topology(triangles, 6);
  ASSERT_EQ(topology.non_manifold_edges.size(), 1u);
  Bvh bvh;
  bvh.build(x, triangles, 0.5);
  const std::vector<TrianglePair> pairs = find_self_pairs(bvh);
  ASSERT_EQ(pairs, (std::vector<TrianglePair>{{2, 3}}));
  const SweptVertexBoxes boxes{x, x, 1.0};
  const CandidateMesh mesh{triangles, topology, {}, &boxes};
  CollisionCandidates every, complete;
  add_self_candidates(pairs, mesh, every, TrianglePairList::any);
  add_self_candidates(pairs, mesh, complete, TrianglePairList::complete);
  EXPECT_EQ(every.edge_edge.size(), 9u);
  EXPECT_TRUE(complete.vertex_face == every.vertex_face);
  EXPECT_TRUE(complete.edge_edge == every.edge_edge);
}

}  // namespace
}  // namespace weft
