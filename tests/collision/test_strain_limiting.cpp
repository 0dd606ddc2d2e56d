// Strain limiting on the candidate motion: edges end at most (1 + limit) times their rest length,
// linear momentum and pinned vertices are kept, velocities follow the position corrections, and
// motion within the limit is not touched.
#include <gtest/gtest.h>

#include <random>

#include "collision/strain_limiting.hpp"
#include "collision_test_scene.hpp"

namespace weft {
namespace {

constexpr int grid = 6;          // vertices per side
constexpr double spacing = 0.1;  // m, rest edge of the grid

// A grid of grid x grid vertices at rest spacing apart (structural and one diagonal edge per
// cell), random masses, vertex 0 pinned or not, and the given random end displacement of every
// vertex.
struct StretchedGrid {
  test::CollisionScene scene;
  std::vector<double> rest_length;

  StretchedGrid(double displacement, unsigned seed, bool pin_corner = true) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_real_distribution<double> mass(0.5, 2.0);
    for (int j = 0; j < grid; ++j) {
      for (int i = 0; i < grid; ++i) {
        const Vec3 v(unit(random), unit(random), unit(random));
        scene.add_vertex(Vec3(i * spacing, j * spacing, 0.0), displacement / scene.h * v,
                         i + j == 0 && pin_corner ? 0.0 : 1.0 / mass(random));
      }
    }
    if (pin_corner) scene.set_velocity(0, Vec3::Zero());
    const auto id = [](int i, int j) { return j * grid + i; };
    for (int j = 0; j < grid; ++j) {
      for (int i = 0; i < grid; ++i) {
        if (i + 1 < grid) scene.add_edge(id(i, j), id(i + 1, j));
        if (j + 1 < grid) scene.add_edge(id(i, j), id(i, j + 1));
        if (i + 1 < grid && j + 1 < grid) scene.add_edge(id(i, j), id(i + 1, j + 1));
      }
    }
    for (int e = 0; e < scene.edges.cols(); ++e) {
      rest_length.push_back(
          (scene.x_start.col(scene.edges(1, e)) - scene.x_start.col(scene.edges(0, e))).norm());
    }
  }

  double largest_strain() const {
    double largest = 0.0;
    for (int e = 0; e < scene.edges.cols(); ++e) {
      const double length = (scene.x_end.col(scene.edges(1, e)) - scene.x_end.col(scene.edges(0, e))).norm();
      largest = std::max(largest, length / rest_length[e] - 1.0);
    }
    return largest;
  }
};

TEST(StrainLimiting, StretchedEdgesEndAtTheLimitKeepingMomentumAndPins) {
  constexpr double limit = 0.1;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    // Displacements up to one rest edge (strains up to ~2); odd seeds pin vertex 0.
    const bool pinned = seed % 2 == 1;
    StretchedGrid cloth(0.1, seed, pinned);
    test::CollisionScene& scene = cloth.scene;
    const double strain_before = cloth.largest_strain();
    ASSERT_GT(strain_before, 1.0);
    const Positions x_end_before = scene.x_end;
    const Positions velocity_before = scene.velocity;
    const Vec3 momentum_before = scene.momentum(scene.velocity);

    CollisionStep step = scene.step();
    const StrainLimitResult result = limit_edge_strain(step, cloth.rest_length, limit, 1000);

    EXPECT_LT(result.sweeps, 1000) << "seed " << seed;
    EXPECT_GT(result.corrected_edges, 0);
    EXPECT_DOUBLE_EQ(result.largest_strain_before, strain_before);
    EXPECT_LE(cloth.largest_strain(), limit + 1e-3 * (1.0 + limit) + 1e-12) << "seed " << seed;
    if (pinned) {
      EXPECT_EQ(scene.x_end.col(0), x_end_before.col(0));
    } else {
      EXPECT_LT((scene.momentum(scene.velocity) - momentum_before).norm(), 1e-10 * momentum_before.norm())
          << "seed " << seed;
    }
    // Every correction of the end position is a velocity change of the same motion.
    const Positions expected_velocity = velocity_before + (scene.x_end - x_end_before) / scene.h;
    EXPECT_LT((scene.velocity - expected_velocity).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(StrainLimiting, MotionWithinTheLimitIsNotTouched) {
  StretchedGrid cloth(0.002, 7);  // displacements of 2% of an edge: strains below 0.1
  test::CollisionScene& scene = cloth.scene;
  ASSERT_LT(cloth.largest_strain(), 0.1);
  const Positions x_end_before = scene.x_end;
  const Positions velocity_before = scene.velocity;
  CollisionStep step = scene.step();
  const StrainLimitResult result = limit_edge_strain(step, cloth.rest_length, 0.1, 1000);
  EXPECT_EQ(result.sweeps, 0);
  EXPECT_EQ(result.corrected_edges, 0);
  EXPECT_GT(result.largest_strain_before, 0.0);
  EXPECT_TRUE(scene.x_end == x_end_before);
  EXPECT_TRUE(scene.velocity == velocity_before);
}

TEST(StrainLimiting, EdgesWithoutRestLengthAndBetweenPinnedVerticesAreLeftAlone) {
  StretchedGrid cloth(0.1, 3);
  test::CollisionScene& scene = cloth.scene;
  // No edge has a rest length (collider edges): nothing moves.
  std::vector<double> no_rest(cloth.rest_length.size(), 0.0);
  const Positions x_end_before = scene.x_end;
  CollisionStep step = scene.step();
  EXPECT_EQ(limit_edge_strain(step, no_rest, 0.1, 1000).corrected_edges, 0);
  EXPECT_TRUE(scene.x_end == x_end_before);
  // Every vertex pinned: the stretched edges stay as they are.
  scene.inverse_mass.setZero();
  CollisionStep pinned = scene.step();
  limit_edge_strain(pinned, cloth.rest_length, 0.1, 1000);
  EXPECT_TRUE(scene.x_end == x_end_before);
}

}  // namespace
}  // namespace weft
