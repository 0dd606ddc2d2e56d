// The stability check names the cloth, the vertex, what went wrong and the force term to blame.
#include <gtest/gtest.h>

#include <cmath>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"

namespace weft {
namespace {

World sheet(double structural_stiffness = 100.0) {
  const auto document = nlohmann::json::parse(R"({
    "cloths": [{"name": "sheet", "grid": {"size": [1, 1], "resolution": [5, 5]},
                "springs": {"structural": {"stiffness": )" +
                                              std::to_string(structural_stiffness) + R"(}}}]
  })");
  return build_world(parse_scene(document, "<inline>"));
}

TEST(Stability, AHealthyClothPasses) {
  World world = sheet();
  for (int step = 0; step < 20; ++step) world.step();
  EXPECT_FALSE(check_state(world, StabilityLimits{}).found);
  EXPECT_FALSE(check_strain(world, StabilityLimits{}).found);
}

TEST(Stability, NonFiniteValuesNameTheVertex) {
  World world = sheet();
  world.cloths()[0].state.v(1, 7) = NAN;
  Instability found = check_state(world, StabilityLimits{});
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.vertex, 7);
  EXPECT_EQ(found.quantity, "velocity");
  EXPECT_NE(found.describe().find("cloth \"sheet\" vertex 7 has a non-finite velocity"), std::string::npos);
  // The spring damping at vertex 7 is non-finite with it: that term is blamed.
  EXPECT_NE(found.term.find("springs"), std::string::npos) << found.term;

  world.cloths()[0].state.v(1, 7) = 0.0;
  world.cloths()[0].state.x(0, 3) = INFINITY;
  found = check_state(world, StabilityLimits{});
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.vertex, 3);
  EXPECT_EQ(found.quantity, "position");
}

TEST(Stability, SpeedPastTheBoundIsFoundAndCanBeTurnedOff) {
  World world = sheet();
  world.cloths()[0].state.v.col(12) = Vec3(0.0, 0.0, 150.0);
  const Instability found = check_state(world, StabilityLimits{100.0, 5.0});
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.vertex, 12);
  EXPECT_EQ(found.quantity, "speed");
  EXPECT_DOUBLE_EQ(found.value, 150.0);
  EXPECT_NE(found.describe().find("moves at 150 m/s"), std::string::npos) << found.describe();
  EXPECT_FALSE(check_state(world, StabilityLimits{0.0, 5.0}).found);
}

TEST(Stability, StrainPastTheBoundBlamesTheStretchedSpringKind) {
  World world = sheet(1e6);
  world.cloths()[0].state.x.col(24) += Vec3(0.0, 0.0, 2.0);  // the last corner pulled far out
  const Instability found = check_strain(world, StabilityLimits{100.0, 1.0});
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.quantity, "strain");
  EXPECT_GT(found.value, 1.0);
  // Blamed on the stiff structural springs that are stretched.
  EXPECT_EQ(found.term, "structural springs");
  EXPECT_NE(found.describe().find("stretched"), std::string::npos);
  EXPECT_FALSE(check_strain(world, StabilityLimits{100.0, 0.0}).found);
  // The largest strain is the one a bound just below it finds, and no bound above it does.
  const double largest = largest_strain(world);
  EXPECT_GE(largest, found.value);
  EXPECT_TRUE(check_strain(world, StabilityLimits{100.0, largest * 0.999}).found);
  EXPECT_FALSE(check_strain(world, StabilityLimits{100.0, largest * 1.001}).found);
}

TEST(Stability, MembraneStrainPastTheBoundNamesTheTriangleAndBlamesTheMembrane) {
  const auto document = nlohmann::json::parse(R"({
    "cloths": [{"name": "sheet", "grid": {"size": [1, 1], "resolution": [5, 5]},
                "springs": {"structural": {"stiffness": 0}, "shear": {"stiffness": 0}, "bend": {"stiffness": 0}},
                "membrane": {"young_modulus": 1e6}}]
  })");
  World world = build_world(parse_scene(document, "<inline>"));
  EXPECT_FALSE(check_strain(world, StabilityLimits{100.0, 0.5}).found);
  world.cloths()[0].state.x.col(24) += Vec3(0.0, 0.0, 2.0);  // the last corner pulled far out
  const Instability found = check_strain(world, StabilityLimits{100.0, 0.5});
  ASSERT_TRUE(found.found);
  EXPECT_EQ(found.quantity, "membrane_strain");
  EXPECT_GT(found.value, 0.5);
  EXPECT_GE(found.element, 0);
  EXPECT_EQ(found.term, "membrane");
  EXPECT_NE(found.describe().find("membrane triangle " + std::to_string(found.element)), std::string::npos)
      << found.describe();
  EXPECT_FALSE(check_strain(world, StabilityLimits{100.0, 0.0}).found);
}

}  // namespace
}  // namespace weft
