// The analytic solids' signed distances: known values for each shape, and a placed solid (turned
// and moved) measuring the same as the unplaced one at the point carried back.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "check/solid_distance.hpp"

namespace weft {
namespace {

TEST(SolidDistance, EachShapeMeasuresFromItsDefinition) {
  AnalyticSolid half_space;
  half_space.kind = SolidKind::half_space;
  half_space.normal = Vec3(0, 2, 0);  // not unit: normalised
  EXPECT_DOUBLE_EQ(reference_signed_distance(half_space, Vec3(5, -0.25, 3)), -0.25);

  AnalyticSolid sphere;
  sphere.kind = SolidKind::sphere;
  sphere.radius = 0.5;
  EXPECT_DOUBLE_EQ(reference_signed_distance(sphere, Vec3(0, 0.46, 0)), -0.04);
  EXPECT_DOUBLE_EQ(reference_signed_distance(sphere, Vec3(0, 0, 2)), 1.5);

  AnalyticSolid box;
  box.kind = SolidKind::box;
  box.half_extents = Vec3(1, 2, 3);
  EXPECT_DOUBLE_EQ(reference_signed_distance(box, Vec3(0.5, 0, 0)), -0.5);
  EXPECT_DOUBLE_EQ(reference_signed_distance(box, Vec3(4, 6, 3)), 5.0);  // (3, 4, 0) from a corner

  AnalyticSolid capsule;
  capsule.kind = SolidKind::capsule;
  capsule.axis = Vec3::UnitX();
  capsule.radius = 0.25;
  capsule.half_length = 1.0;
  EXPECT_DOUBLE_EQ(reference_signed_distance(capsule, Vec3(0.9, 0.1, 0)), -0.15);
  EXPECT_DOUBLE_EQ(reference_signed_distance(capsule, Vec3(2, 0, 0)), 0.75);

  AnalyticSolid cylinder;
  cylinder.kind = SolidKind::capped_cylinder;
  cylinder.axis = Vec3::UnitY();
  cylinder.radius = 1.0;
  cylinder.half_length = 0.5;
  EXPECT_DOUBLE_EQ(reference_signed_distance(cylinder, Vec3(0, 0.4, 0)), -0.1);
  EXPECT_DOUBLE_EQ(reference_signed_distance(cylinder, Vec3(0, 1.5, 0)), 1.0);
}

TEST(SolidDistance, APlacedSolidMeasuresAtThePointCarriedBack) {
  AnalyticSolid box;
  box.kind = SolidKind::box;
  box.half_extents = Vec3(0.3, 0.1, 0.2);
  AnalyticSolid placed = box;
  placed.orientation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  placed.center = Vec3(1, -2, 0.5);
  for (const Vec3& local : {Vec3(0.1, 0.05, -0.1), Vec3(0.5, 0.3, 0.0), Vec3(-0.29, 0, 0.19)}) {
    const Vec3 p = placed.orientation * local + placed.center;
    EXPECT_NEAR(reference_signed_distance(placed, p), reference_signed_distance(box, local), 1e-14);
  }
}

}  // namespace
}  // namespace weft
