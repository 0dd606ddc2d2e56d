// Broad phase: the BVH's triangle pairs equal brute force (every pair whose swept, inflated
// boxes overlap) on random soups, flat and crumpled grids, after refits, for self, two-mesh and
// box queries, at any thread count; the tree's invariants; the rebuild trigger.
#include "collision/bvh.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <iterator>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/mesh_generators.hpp"
#include "support/bvh_pairs.hpp"

namespace weft {
namespace {

// Triangles that each get three vertices of their own near a random centre, some of which are
// then replaced by a vertex of an earlier triangle, so that some pairs share a vertex.
TriangleMesh random_soup(int num_triangles, double size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> offset(-size, size);
  TriangleMesh mesh;
  mesh.positions.resize(3, 3 * num_triangles);
  mesh.triangles.resize(3, num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    const Vec3 centre(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k) {
      mesh.positions.col(3 * t + k) = centre + Vec3(offset(rng), offset(rng), offset(rng));
      mesh.triangles(k, t) = 3 * t + k;
    }
    if (t > 0 && unit(rng) < 0.3) {
      const int other = std::uniform_int_distribution<int>(0, t - 1)(rng);
      mesh.triangles(0, t) = mesh.triangles(std::uniform_int_distribution<int>(0, 2)(rng), other);
    }
  }
  return mesh;
}

// A grid in the unit square, squeezed sideways and folded in waves with noise of about one
// spacing, so that distant parts of the cloth come close, as in a crumpled cloth.
TriangleMesh crumpled_grid(int n, unsigned seed) {
  TriangleMesh mesh = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
  std::mt19937 rng(seed);
  const double spacing = 1.0 / (n - 1);
  std::uniform_real_distribution<double> noise(-0.5 * spacing, 0.5 * spacing);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * pi);
  const double phase_x = phase(rng), phase_y = phase(rng);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.positions(0, v), y = mesh.positions(1, v);
    mesh.positions.col(v) = Vec3(0.6 * x + 0.05 * std::sin(9.0 * y + phase_y), 0.6 * y,
                                 0.15 * std::sin(11.0 * x + phase_x) * std::cos(7.0 * y)) +
                            Vec3(noise(rng), noise(rng), noise(rng));
  }
  return mesh;
}

Positions displaced(const Positions& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  Positions moved = x;
  for (Eigen::Index v = 0; v < x.cols(); ++v) moved.col(v) += Vec3(noise(rng), noise(rng), noise(rng));
  return moved;
}

// The reference boxes: each triangle's six corner positions, min and max, then the margin.
std::vector<Aabb> reference_boxes(const Positions& x_start, const Positions& x_end,
                                  const Triangles& triangles, double margin) {
  std::vector<Aabb> boxes(triangles.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    Vec3 lower = x_start.col(triangles(0, t)), upper = lower;
    for (int k = 0; k < 3; ++k) {
      for (const Positions* x : {&x_start, &x_end}) {
        lower = lower.cwiseMin(Vec3(x->col(triangles(k, t))));
        upper = upper.cwiseMax(Vec3(x->col(triangles(k, t))));
      }
    }
    boxes[t].lower = lower - Vec3::Constant(margin);
    boxes[t].upper = upper + Vec3::Constant(margin);
  }
  return boxes;
}

bool boxes_overlap(const Aabb& a, const Aabb& b) {
  for (int i = 0; i < 3; ++i) {
    if (a.upper[i] < b.lower[i] || b.upper[i] < a.lower[i]) return false;
  }
  return true;
}

bool share_a_vertex(const Triangles& triangles, int s, int t) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (triangles(i, s) == triangles(j, t)) return true;
    }
  }
  return false;
}

std::vector<TrianglePair> brute_force_self(const Positions& x_start, const Positions& x_end,
                                           const Triangles& triangles, double margin,
                                           bool keep_neighbours = false) {
  const std::vector<Aabb> boxes = reference_boxes(x_start, x_end, triangles, margin);
  std::vector<TrianglePair> pairs;
  for (int s = 0; s < triangles.cols(); ++s) {
    for (int t = s + 1; t < triangles.cols(); ++t) {
      if (!keep_neighbours && share_a_vertex(triangles, s, t)) continue;
      if (boxes_overlap(boxes[s], boxes[t])) pairs.push_back({s, t});
    }
  }
  return pairs;
}

std::vector<TrianglePair> brute_force_between(const TriangleMesh& first, const TriangleMesh& second,
                                              double margin) {
  const std::vector<Aabb> boxes_a =
      reference_boxes(first.positions, first.positions, first.triangles, margin);
  const std::vector<Aabb> boxes_b =
      reference_boxes(second.positions, second.positions, second.triangles, margin);
  std::vector<TrianglePair> pairs;
  for (int s = 0; s < first.num_triangles(); ++s) {
    for (int t = 0; t < second.num_triangles(); ++t) {
      if (boxes_overlap(boxes_a[s], boxes_b[t])) pairs.push_back({s, t});
    }
  }
  return pairs;
}

// Structure: preorder layout, every triangle in exactly one leaf, boxes nested, escape indices.
void expect_valid_tree(const Bvh& bvh) {
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const int num_nodes = static_cast<int>(nodes.size());
  std::vector<int> seen(bvh.num_triangles(), 0);
  for (int i = 0; i < num_nodes; ++i) {
    const BvhNode& node = nodes[i];
    if (node.is_leaf()) {
      EXPECT_LE(node.count, bvh.settings().max_leaf_size);
      EXPECT_EQ(node.next, i + 1);
      for (int k = 0; k < node.count; ++k) {
        const int t = bvh.triangle_order()[node.first + k];
        ++seen[t];
        const Aabb& box = bvh.triangle_boxes()[t];
        EXPECT_TRUE((node.box.lower.array() <= box.lower.array()).all() &&
                    (box.upper.array() <= node.box.upper.array()).all());
      }
    } else {
      ASSERT_GT(node.right, i + 1);
      ASSERT_LT(node.right, num_nodes);
      EXPECT_EQ(nodes[i + 1].next, node.right) << "left subtree ends where the right child starts";
      EXPECT_EQ(node.next, nodes[node.right].next);
      for (const int child : {i + 1, node.right}) {
        EXPECT_TRUE((node.box.lower.array() <= nodes[child].box.lower.array()).all() &&
                    (nodes[child].box.upper.array() <= node.box.upper.array()).all());
      }
    }
  }
  if (num_nodes > 0) {
    EXPECT_EQ(nodes[0].next, num_nodes);
  }
  for (int t = 0; t < bvh.num_triangles(); ++t) {
    EXPECT_EQ(seen[t], 1) << "triangle " << t;
  }
}

TEST(Bvh, TreeIsValidForEverySettingAndMesh) {
  for (const int leaf_size : {1, 2, 4, 8}) {
    BvhSettings settings;
    settings.max_leaf_size = leaf_size;
    const TriangleMesh soup = random_soup(300, 0.05, 3);
    const TriangleMesh grid = crumpled_grid(17, 4);
    Bvh bvh;
    bvh.build(soup.positions, soup.triangles, 0.01, settings);
    expect_valid_tree(bvh);
    bvh.build(grid.positions, grid.triangles, 0.01, settings);
    expect_valid_tree(bvh);
    bvh.refit(displaced(grid.positions, 0.05, 5), 0.01);
    expect_valid_tree(bvh);
  }
}

TEST(Bvh, TriangleBoxesAreSweptAndInflated) {
  const TriangleMesh soup = random_soup(50, 0.05, 1);
  const Positions x_end = displaced(soup.positions, 0.1, 2);
  Bvh bvh;
  bvh.build(soup.positions, x_end, soup.triangles, 0.003);
  const std::vector<Aabb> expected = reference_boxes(soup.positions, x_end, soup.triangles, 0.003);
  for (int t = 0; t < soup.num_triangles(); ++t) {
    EXPECT_EQ(bvh.triangle_boxes()[t].lower, expected[t].lower);
    EXPECT_EQ(bvh.triangle_boxes()[t].upper, expected[t].upper);
  }
}

TEST(Bvh, SelfPairsMatchBruteForceOnRandomSoups) {
  for (unsigned seed = 0; seed < 6; ++seed) {
    const TriangleMesh soup = random_soup(400, 0.04, seed);
    const Positions x_end = displaced(soup.positions, 0.02, seed + 100);
    const double margin = 0.005 * seed;
    Bvh bvh;
    bvh.build(soup.positions, x_end, soup.triangles, margin);
    const std::vector<TrianglePair> expected =
        brute_force_self(soup.positions, x_end, soup.triangles, margin);
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(testing::self_pairs(bvh), expected) << "seed " << seed;
  }
}

TEST(Bvh, SelfPairsMatchBruteForceOnFlatGrid) {
  const TriangleMesh grid = make_grid(24, 20, 1.0, 0.8, GridTriangulation::regular);
  const double spacing = 1.0 / 23;
  for (const double margin : {0.0, 0.1 * spacing, 0.6 * spacing}) {
    Bvh bvh;
    bvh.build(grid.positions, grid.triangles, margin);
    const std::vector<TrianglePair> pairs = testing::self_pairs(bvh);
    EXPECT_EQ(pairs, brute_force_self(grid.positions, grid.positions, grid.triangles, margin));
    // Neighbours through a vertex never appear.
    for (const TrianglePair& pair : pairs) {
      EXPECT_LT(pair.a, pair.b);
      EXPECT_FALSE(share_a_vertex(grid.triangles, pair.a, pair.b));
    }
  }
}

TEST(Bvh, SelfPairsMatchBruteForceOnCrumpledGrids) {
  for (unsigned seed = 0; seed < 4; ++seed) {
    const TriangleMesh grid = crumpled_grid(25, seed);
    const Positions x_end = displaced(grid.positions, 0.01, seed + 7);
    Bvh bvh;
    bvh.build(grid.positions, x_end, grid.triangles, 0.004);
    const std::vector<TrianglePair> expected = brute_force_self(grid.positions, x_end, grid.triangles, 0.004);
    EXPECT_GT(expected.size(), 500u);
    EXPECT_EQ(testing::self_pairs(bvh), expected) << "seed " << seed;
  }
}

TEST(Bvh, SelfPairsCanKeepNeighbours) {
  for (unsigned seed = 0; seed < 2; ++seed) {
    const TriangleMesh grid = crumpled_grid(21, seed + 80);
    const TriangleMesh soup = random_soup(300, 0.05, seed + 90);
    for (const TriangleMesh* mesh : std::vector<const TriangleMesh*>{&grid, &soup}) {
      Bvh bvh;
      bvh.build(mesh->positions, mesh->triangles, 0.004);
      const std::vector<TrianglePair> all = testing::self_pairs(bvh, testing::SharedVertexPairs::keep);
      EXPECT_EQ(all, brute_force_self(mesh->positions, mesh->positions, mesh->triangles, 0.004, true));
      // The extra pairs are exactly the neighbours.
      const std::vector<TrianglePair> skipped = testing::self_pairs(bvh);
      std::vector<TrianglePair> neighbours;
      std::set_difference(all.begin(), all.end(), skipped.begin(), skipped.end(), std::back_inserter(neighbours));
      EXPECT_EQ(neighbours.size() + skipped.size(), all.size());
      for (const TrianglePair& pair : neighbours) EXPECT_TRUE(share_a_vertex(mesh->triangles, pair.a, pair.b));
    }
  }
}

TEST(Bvh, RefitMatchesBruteForceAtNewPositions) {
  const TriangleMesh grid = crumpled_grid(21, 11);
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.003);
  Positions x_start = grid.positions;
  for (int step = 0; step < 5; ++step) {
    const Positions x_end = displaced(x_start, 0.01, 50 + step);
    bvh.refit(x_start, x_end, 0.003);
    const std::vector<TrianglePair> pairs = testing::self_pairs(bvh);
    EXPECT_EQ(pairs, brute_force_self(x_start, x_end, grid.triangles, 0.003)) << "step " << step;
    // A tree built afresh at these positions finds the same pairs.
    Bvh fresh;
    fresh.build(x_start, x_end, grid.triangles, 0.003);
    EXPECT_EQ(testing::self_pairs(fresh), pairs);
    x_start = x_end;
  }
}

TEST(Bvh, RefitOfMovedVerticesMatchesAFullRefit) {
  // The collision phase's verification grows the boxes of a few vertices and refits only what
  // they touch (refit_moved): every box, the leaf order's copies and the cost must be those a
  // full refit computes.
  const TriangleMesh grid = crumpled_grid(21, 11);
  const Positions x_end = displaced(grid.positions, 0.01, 77);
  Bvh partial, full;
  partial.build(grid.positions, x_end, grid.triangles, 0.003);
  full.build(grid.positions, x_end, grid.triangles, 0.003);
  Positions grown_end = x_end;
  std::vector<char> moved(grid.positions.cols(), 0);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(grid.positions.cols()) - 1);
  for (int round = 0; round < 3; ++round) {
    std::fill(moved.begin(), moved.end(), 0);
    for (int k = 0; k < 6; ++k) {
      const int v = vertex(rng);
      grown_end.col(v) += Vec3(0.02, -0.01, 0.015);
      moved[v] = 1;
    }
    partial.refit_moved(grid.positions, grown_end, 0.003, moved);
    full.refit(grid.positions, grown_end, 0.003);
    ASSERT_EQ(partial.nodes().size(), full.nodes().size());
    for (size_t i = 0; i < full.nodes().size(); ++i) {
      EXPECT_EQ(partial.nodes()[i].box.lower, full.nodes()[i].box.lower) << "node " << i;
      EXPECT_EQ(partial.nodes()[i].box.upper, full.nodes()[i].box.upper) << "node " << i;
    }
    for (int t = 0; t < full.num_triangles(); ++t) {
      EXPECT_EQ(partial.triangle_boxes()[t].lower, full.triangle_boxes()[t].lower);
      EXPECT_EQ(partial.leaf_boxes()[t].upper, full.leaf_boxes()[t].upper);
    }
    EXPECT_EQ(partial.cost(), full.cost());
    EXPECT_GT(full.cost(), full.cost_at_build()) << "the grown boxes loosened the tree";
  }
  EXPECT_THROW(partial.refit_moved(grid.positions, grown_end, 0.003, std::vector<char>(3, 0)),
               std::invalid_argument);
}

TEST(Bvh, PairsBetweenTwoMeshesMatchBruteForce) {
  TriangleMesh cloth = crumpled_grid(19, 21);
  TriangleMesh other = crumpled_grid(15, 22);
  transform_positions(other.positions, rotation_from_euler_degrees(Vec3(20.0, 70.0, 0.0)), 0.8,
                      Vec3(0.1, 0.1, 0.0));
  const TriangleMesh soup = random_soup(200, 0.05, 23);
  const TriangleMesh single = random_soup(1, 0.3, 24);
  for (const TriangleMesh* second : std::vector<const TriangleMesh*>{&other, &soup, &cloth, &single}) {
    Bvh a, b;
    a.build(cloth.positions, cloth.triangles, 0.004);
    b.build(second->positions, second->triangles, 0.004);
    const std::vector<TrianglePair> expected = brute_force_between(cloth, *second, 0.004);
    EXPECT_EQ(testing::pairs_between(a, b), expected);
    // Swapping the meshes swaps each pair.
    std::vector<TrianglePair> swapped = testing::pairs_between(b, a);
    for (TrianglePair& pair : swapped) std::swap(pair.a, pair.b);
    std::sort(swapped.begin(), swapped.end());
    EXPECT_EQ(swapped, expected);
  }
  // A mesh against a copy of itself: every triangle pair whose boxes overlap, shared corners
  // included, since the two are different meshes.
  Bvh a, b;
  a.build(cloth.positions, cloth.triangles, 0.0);
  b.build(cloth.positions, cloth.triangles, 0.0);
  const std::vector<TrianglePair> pairs = testing::pairs_between(a, b);
  for (int t = 0; t < cloth.num_triangles(); ++t) {
    EXPECT_TRUE(std::binary_search(pairs.begin(), pairs.end(), TrianglePair{t, t}));
  }
}

TEST(Bvh, BoxQueryMatchesBruteForce) {
  const TriangleMesh grid = crumpled_grid(30, 31);
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.002);
  const std::vector<Aabb> boxes = reference_boxes(grid.positions, grid.positions, grid.triangles, 0.002);
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> unit(-0.1, 0.7);
  std::uniform_real_distribution<double> size(0.0, 0.2);
  std::vector<int> found;
  int total = 0;
  for (int query = 0; query < 50; ++query) {
    Aabb box;
    box.lower = Vec3(unit(rng), unit(rng), unit(rng) - 0.3);
    box.upper = box.lower + Vec3(size(rng), size(rng), size(rng));
    find_triangles_in_box(bvh, box, found);
    std::vector<int> expected;
    for (int t = 0; t < grid.num_triangles(); ++t) {
      if (boxes_overlap(boxes[t], box)) expected.push_back(t);
    }
    EXPECT_EQ(found, expected) << "query " << query;
    total += static_cast<int>(expected.size());
  }
  EXPECT_GT(total, 100);
  find_triangles_in_box(bvh, Aabb(), found);
  EXPECT_TRUE(found.empty()) << "an empty box overlaps nothing";
}

TEST(Bvh, ResultsIdenticalAtOneAndTwoThreads) {
  const int threads_before = omp_get_max_threads();
  const TriangleMesh grid = crumpled_grid(40, 41);
  const TriangleMesh other = crumpled_grid(30, 42);
  const Positions x_end = displaced(grid.positions, 0.01, 43);
  std::vector<std::vector<TrianglePair>> self_results, between_results;
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    Bvh bvh, other_bvh;
    bvh.build(grid.positions, grid.triangles, 0.003);
    bvh.refit(grid.positions, x_end, 0.003);
    other_bvh.build(other.positions, other.triangles, 0.003);
    self_results.push_back(testing::self_pairs(bvh));
    between_results.push_back(testing::pairs_between(bvh, other_bvh));
  }
  omp_set_num_threads(threads_before);
  EXPECT_GT(self_results[0].size(), 1000u);
  EXPECT_GT(between_results[0].size(), 1000u);
  EXPECT_EQ(self_results[0], self_results[1]);
  EXPECT_EQ(self_results[0], self_results[2]);
  EXPECT_EQ(between_results[0], between_results[1]);
  EXPECT_EQ(between_results[0], between_results[2]);
}

TEST(Bvh, RebuildTriggerFiresWhenScrambled) {
  const TriangleMesh grid = crumpled_grid(32, 61);
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.003);
  EXPECT_DOUBLE_EQ(bvh.degradation(), 1.0);
  EXPECT_FALSE(bvh.needs_rebuild());

  // Small motion, a rigid motion and uniform scaling leave the tree as good as built.
  bvh.refit(displaced(grid.positions, 0.002, 62), 0.003);
  EXPECT_LT(bvh.degradation(), 1.2);
  EXPECT_FALSE(bvh.needs_rebuild());
  Positions moved = grid.positions;
  transform_positions(moved, rotation_from_euler_degrees(Vec3(30.0, 10.0, 45.0)), 3.0, Vec3(1.0, 2.0, 3.0));
  bvh.refit(moved, 0.009);
  EXPECT_LT(bvh.degradation(), 1.2);
  EXPECT_FALSE(bvh.needs_rebuild());

  // Vertices shuffled among themselves: every leaf now spans the whole cloth.
  std::vector<int> permutation(grid.num_vertices());
  std::iota(permutation.begin(), permutation.end(), 0);
  std::shuffle(permutation.begin(), permutation.end(), std::mt19937(63));
  Positions scrambled(3, grid.num_vertices());
  for (int v = 0; v < grid.num_vertices(); ++v) scrambled.col(v) = grid.positions.col(permutation[v]);
  bvh.refit(scrambled, 0.003);
  EXPECT_GT(bvh.degradation(), 10.0);
  EXPECT_TRUE(bvh.needs_rebuild());
  // Pairs are still right before the rebuild, and a rebuild restores the quality.
  EXPECT_EQ(testing::self_pairs(bvh), brute_force_self(scrambled, scrambled, grid.triangles, 0.003));
  bvh.build(scrambled, grid.triangles, 0.003);
  EXPECT_FALSE(bvh.needs_rebuild());
}

TEST(Bvh, EmptyAndTinyMeshes) {
  Bvh bvh;
  bvh.build(Positions(3, 0), Triangles(3, 0), 0.01);
  EXPECT_TRUE(bvh.nodes().empty());
  EXPECT_TRUE(testing::self_pairs(bvh).empty());
  bvh.refit(Positions(3, 0), 0.01);
  std::vector<int> found;
  find_triangles_in_box(bvh, Aabb{Vec3::Constant(-1.0), Vec3::Constant(1.0)}, found);
  EXPECT_TRUE(found.empty());

  const TriangleMesh one = random_soup(1, 0.1, 71);
  Bvh single;
  single.build(one.positions, one.triangles, 0.01);
  EXPECT_EQ(single.nodes().size(), 1u);
  EXPECT_TRUE(testing::self_pairs(single).empty());
  EXPECT_TRUE(testing::pairs_between(single, bvh).empty());
  EXPECT_EQ(testing::pairs_between(single, single), (std::vector<TrianglePair>{{0, 0}}));

  // Every triangle at one point: no split plane exists, the build still halves the ranges.
  Positions collapsed = Positions::Zero(3, 30);
  Triangles triangles(3, 10);
  for (int t = 0; t < 10; ++t) triangles.col(t) = Vec3i(3 * t, 3 * t + 1, 3 * t + 2);
  Bvh point;
  point.build(collapsed, triangles, 0.0);
  expect_valid_tree(point);
  EXPECT_EQ(testing::self_pairs(point).size(), 45u);
}

TEST(Bvh, RejectsBadInput) {
  const TriangleMesh grid = make_grid(3, 3, 1.0, 1.0, GridTriangulation::regular);
  Bvh bvh;
  EXPECT_THROW(bvh.build(grid.positions, Positions(3, 2), grid.triangles, 0.0), std::invalid_argument);
  EXPECT_THROW(bvh.build(grid.positions, grid.triangles, -1.0), std::invalid_argument);
  Triangles bad = grid.triangles;
  bad(1, 2) = 9;
  EXPECT_THROW(bvh.build(grid.positions, bad, 0.0), std::invalid_argument);
  bvh.build(grid.positions, grid.triangles, 0.0);
  EXPECT_THROW(bvh.refit(Positions(3, 4), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace weft
