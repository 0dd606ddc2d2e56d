// Self-collision culling: which regions are disks; a flat sheet is culled whole and a folded one
// keeps its fold's pairs; and, over random smooth and crumpled motions, every triangle pair the
// culling drops stays apart (exact intersection check) all through the step.
#include "collision/self_culling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <vector>

#include "check/intersection_check.hpp"
#include "core/mesh_generators.hpp"
#include "support/bvh_pairs.hpp"

namespace weft {
namespace {

std::vector<TrianglePair> culled_pairs(const Bvh& bvh, SelfCulling& culling, const Positions& x_start,
                                       const Positions& x_end, double margin) {
  culling.update(bvh, x_start, x_end, margin);
  return testing::self_pairs(bvh, testing::SharedVertexPairs::keep, &culling.culled());
}

TEST(SelfCulling, GridIsADiskAndTheRootOfAnAnnulusOrOfTwoPiecesIsNot) {
  const TriangleMesh grid = make_grid(12, 12, 1.0, 1.0, GridTriangulation::alternating);
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.0);
  SelfCulling culling;
  culling.prepare(bvh);
  EXPECT_TRUE(culling.disks()[0]);

  // An annulus: the grid without its four central quads.
  std::vector<int> kept;
  for (int t = 0; t < grid.triangles.cols(); ++t) {
    const Vec3 centre = (grid.positions.col(grid.triangles(0, t)) + grid.positions.col(grid.triangles(1, t)) +
                         grid.positions.col(grid.triangles(2, t))) / 3.0;
    if (centre.cwiseAbs().maxCoeff() > 0.1) kept.push_back(t);
  }
  Triangles annulus(3, static_cast<Eigen::Index>(kept.size()));
  for (size_t k = 0; k < kept.size(); ++k) annulus.col(static_cast<Eigen::Index>(k)) = grid.triangles.col(kept[k]);
  bvh.build(grid.positions, annulus, 0.0);
  culling.prepare(bvh);
  EXPECT_FALSE(culling.disks()[0]);
  EXPECT_TRUE(std::any_of(culling.disks().begin(), culling.disks().end(), [](char d) { return d != 0; }))
      << "parts of the annulus are disks";

  // Two grids side by side, not joined.
  Positions two(3, 2 * grid.positions.cols());
  two << grid.positions, grid.positions.colwise() + Vec3(2.0, 0.0, 0.0);
  Triangles both(3, 2 * grid.triangles.cols());
  both << grid.triangles, grid.triangles.array() + static_cast<int>(grid.positions.cols());
  bvh.build(two, both, 0.0);
  culling.prepare(bvh);
  EXPECT_FALSE(culling.disks()[0]);
}

TEST(SelfCulling, FlatFallingSheetIsCulledWhole) {
  const TriangleMesh grid = make_grid(20, 20, 1.0, 1.0, GridTriangulation::alternating);
  Positions x_end = grid.positions;
  x_end.row(2).array() -= 0.01;
  Bvh bvh;
  bvh.build(grid.positions, x_end, grid.triangles, 0.0025);
  ASSERT_FALSE(testing::self_pairs(bvh).empty()) << "without culling the flat sheet has candidate pairs";
  SelfCulling culling;
  EXPECT_TRUE(culled_pairs(bvh, culling, grid.positions, x_end, 0.005).empty());
  EXPECT_TRUE(culling.culled()[0]);
  EXPECT_EQ(culling.stats().triangles_culled, grid.triangles.cols());

  SelfCullingSettings off;
  off.enabled = false;
  culling.update(bvh, grid.positions, x_end, 0.005, off);
  EXPECT_EQ(testing::self_pairs(bvh, testing::SharedVertexPairs::skip, &culling.culled()),
            testing::self_pairs(bvh))
      << "culling off changes nothing";
}

// The collision phase updates the culling again on its corrected motion, where few vertices moved:
// the update then decides again only the nodes holding a moved vertex (or newly reached), and must
// flag exactly what a fresh culling decides, through a crumple that breaks culled regions and the
// motion put back.
TEST(SelfCulling, AnUpdateOnChangedMotionDecidesAsAFreshOne) {
  const TriangleMesh grid = make_grid(24, 24, 1.0, 1.0, GridTriangulation::alternating);
  Positions x_end = grid.positions;
  for (int v = 0; v < x_end.cols(); ++v) x_end(2, v) = 0.02 * std::sin(3.0 * x_end(0, v)) - 0.01;
  Bvh bvh;
  bvh.build(grid.positions, x_end, grid.triangles, 0.0025);
  SelfCulling kept;
  kept.update(bvh, grid.positions, x_end, 0.005);
  const std::vector<char> smooth = kept.culled();

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  Positions crumpled = x_end;
  for (int v = 0; v < crumpled.cols(); ++v) {
    if (crumpled(0, v) > 0.2 && crumpled(1, v) > 0.2)
      crumpled.col(v) += Vec3(jitter(rng), jitter(rng), jitter(rng));
  }
  for (const Positions* motion : {&crumpled, &x_end, &crumpled}) {
    kept.update(bvh, grid.positions, *motion, 0.005);
    SelfCulling fresh;
    fresh.update(bvh, grid.positions, *motion, 0.005);
    EXPECT_EQ(kept.culled(), fresh.culled());
    EXPECT_EQ(kept.stats().nodes_tested, fresh.stats().nodes_tested);
    EXPECT_EQ(kept.stats().nodes_culled, fresh.stats().nodes_culled);
    EXPECT_EQ(kept.stats().triangles_culled, fresh.stats().triangles_culled);
  }
  EXPECT_NE(kept.culled(), smooth) << "the crumple broke culled regions";
}

// A sheet folded over itself with a 4 mm gap (the folded part mirrored onto the rest): the root cannot be culled (its normals point both
// ways), and every pair between the two layers is still reported.
TEST(SelfCulling, FoldedSheetKeepsThePairsBetweenItsLayers) {
  const int n = 21;
  const TriangleMesh grid = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
  Positions x = grid.positions;
  for (int v = 0; v < x.cols(); ++v) {
    const double s = x(0, v);  // the part right of x = 0.1 mirrored back over the left, 4 mm up
    if (s > 0.1 + 1e-9) {
      x(0, v) = 0.2 - s;
      x(2, v) = 0.004;
    }
  }
  Bvh bvh;
  bvh.build(x, grid.triangles, 0.0025);
  const std::vector<TrianglePair> all = testing::self_pairs(bvh, testing::SharedVertexPairs::keep);
  SelfCulling culling;
  const std::vector<TrianglePair> kept = culled_pairs(bvh, culling, x, x, 0.005);
  EXPECT_FALSE(culling.culled()[0]);
  int between_layers = 0;
  for (const TrianglePair& pair : all) {
    const double za = x(2, grid.triangles(0, pair.a)) + x(2, grid.triangles(1, pair.a)) + x(2, grid.triangles(2, pair.a));
    const double zb = x(2, grid.triangles(0, pair.b)) + x(2, grid.triangles(1, pair.b)) + x(2, grid.triangles(2, pair.b));
    if (std::abs(za - zb) < 0.009) continue;  // both in one layer
    ++between_layers;
    EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), pair)) << pair.a << " " << pair.b;
  }
  EXPECT_GT(between_layers, 50);
  EXPECT_LT(kept.size(), all.size()) << "the flat parts of each layer are culled";
}

// Random motions of a grid, from gentle waves to crumpling: the culled query is a subset of the
// full one, and no pair it drops intersects (by the standard definition, neighbours included) at
// any of 9 times through the step.
TEST(SelfCulling, DroppedPairsNeverIntersectDuringTheStep) {
  const int n = 16;
  const TriangleMesh grid = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int dropped_total = 0;
  int trials_with_culling = 0;
  int roots_culled = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double amplitude = 0.02 * (trial % 10);  // 0 (flat) .. 0.18 m (steep, folding waves)
    const double noise = trial % 4 == 3 ? 0.03 : 0.002;
    const auto shape = [&](double phase_x, double phase_y, double k) {
      Positions x = grid.positions;
      for (int v = 0; v < x.cols(); ++v) {
        x(2, v) += amplitude * std::sin(k * x(0, v) + phase_x) * std::cos(k * x(1, v) + phase_y);
        x.col(v) += noise * Vec3(unit(rng), unit(rng), unit(rng));
      }
      return x;
    };
    const double k = 4.0 + 8.0 * (unit(rng) + 1.0);
    const double px = 3.0 * unit(rng), py = 3.0 * unit(rng);
    const Positions x_start = shape(px, py, k);
    const Positions x_end = shape(px + 0.5 * unit(rng), py + 0.5 * unit(rng), k);
    Bvh bvh;
    bvh.build(x_start, x_end, grid.triangles, 0.0025);
    const std::vector<TrianglePair> all = testing::self_pairs(bvh, testing::SharedVertexPairs::keep);
    SelfCulling culling;
    const std::vector<TrianglePair> kept = culled_pairs(bvh, culling, x_start, x_end, 0.005);
    ASSERT_TRUE(std::includes(all.begin(), all.end(), kept.begin(), kept.end())) << "trial " << trial;
    std::vector<TrianglePair> dropped;
    std::set_difference(all.begin(), all.end(), kept.begin(), kept.end(), std::back_inserter(dropped));
    dropped_total += static_cast<int>(dropped.size());
    trials_with_culling += culling.stats().nodes_culled > 0;
    roots_culled += culling.culled()[0];
    for (int step = 0; step <= 8; ++step) {
      const double t = step / 8.0;
      const Positions x = (1.0 - t) * x_start + t * x_end;
      for (const TriangleIntersection& hit : find_triangle_intersections(x, grid.triangles)) {
        const TrianglePair pair{hit.triangle_a, hit.triangle_b};
        ASSERT_FALSE(std::binary_search(dropped.begin(), dropped.end(), pair))
            << "trial " << trial << " t " << t << " dropped pair " << pair.a << " " << pair.b;
      }
    }
  }
  EXPECT_GT(dropped_total, 1000) << "culling drops pairs";
  EXPECT_GT(trials_with_culling, 10);
  EXPECT_GT(roots_culled, 0) << "nearly flat sheets are culled whole";
  EXPECT_LT(roots_culled, 40) << "steep and crumpled sheets are not";
}

// A strip wound 1.2 turns as a shallow ramp (normals within a few degrees of vertical, a disk),
// whose last 0.2 turn lies 2 cm above its first at the start of the step and 2 cm below at the
// end: it passes through itself. Only the contour test sees that; the pairs it passes through
// must all be kept.
TEST(SelfCulling, RampPassingThroughItselfKeepsItsCollidingPairs) {
  const int nu = 97, nv = 5;
  const TriangleMesh grid = make_grid(nu, nv, 1.0, 1.0, GridTriangulation::alternating);
  const double turns = 1.2;
  const auto wind = [&](double rise) {
    Positions x(3, grid.positions.cols());
    for (int i = 0; i < x.cols(); ++i) {
      const double u = (grid.positions(0, i) + 0.5) * turns * 2.0 * M_PI;
      const double r = 0.3 + 0.1 * (grid.positions(1, i) + 0.5);
      x.col(i) = Vec3(r * std::cos(u), r * std::sin(u), rise * u / (2.0 * M_PI));
    }
    return x;
  };
  const Positions x_start = wind(0.02);
  const Positions x_end = wind(-0.02);
  Bvh bvh;
  bvh.build(x_start, x_end, grid.triangles, 0.0025);
  SelfCulling culling;
  const std::vector<TrianglePair> kept = culled_pairs(bvh, culling, x_start, x_end, 0.005);
  const Positions middle = 0.5 * (x_start + x_end);  // flat: the overlapping turns coincide
  int colliding = 0;
  for (const TriangleIntersection& hit : find_triangle_intersections(middle, grid.triangles)) {
    ++colliding;
    const TrianglePair pair{hit.triangle_a, hit.triangle_b};
    EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), pair)) << pair.a << " " << pair.b;
  }
  EXPECT_GT(colliding, 20) << "the ramp does pass through itself";
  EXPECT_FALSE(culling.culled()[0]);
  EXPECT_GT(culling.stats().nodes_culled, 0) << "single-turn pieces of the ramp are culled";
}

}  // namespace
}  // namespace weft
