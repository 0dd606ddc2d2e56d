// Rigid impact zones as the strain limit's fail-safe: with a bound, edges the Gauss-Seidel
// limiter left over it join zones, whose rigid motion keeps them at their start length, and an
// edge a zone's rigid motion stretches pulls its free end into the zone; within the limit nothing
// moves. (Zones against collisions are exercised through CollisionPhase and the scene tests.)
#include "collision/impact_zones.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "collision_test_scene.hpp"

namespace weft {
namespace {

// A strip of `count` vertices 0.1 m apart along x, joined by edges, each moving by `end_shift(i)`.
struct Strip {
  test::CollisionScene scene;
  std::vector<double> rest_length;

  template <typename Shift>
  Strip(int count, Shift end_shift) {
    for (int i = 0; i < count; ++i) scene.add_vertex(Vec3(0.1 * i, 0.0, 0.0), end_shift(i) / scene.h, 1.0);
    for (int i = 0; i + 1 < count; ++i) {
      scene.add_edge(i, i + 1);
      rest_length.push_back(0.1);
    }
  }

  double length_at_end(int e) const {
    return (scene.x_end.col(scene.edges(1, e)) - scene.x_end.col(scene.edges(0, e))).norm();
  }
};

TEST(ImpactZones, EdgesOverTheStrainLimitMoveRigidlyToTheirStartLength) {
  // Vertex 3 of 6 pulled 0.5 m up: edges 2-3 and 3-4 at ~5x their rest length.
  Strip strip(6, [](int i) { return i == 3 ? Vec3(0.0, 0.5, 0.0) : Vec3::Zero(); });
  CollisionStep step = strip.scene.step();
  const StrainBound bound{strip.rest_length, 1.0};
  ASSERT_TRUE(edge_over_limit(step, bound, 2));
  ImpactZoneWorkspace workspace;
  const ImpactZoneResult result = resolve_impact_zones(step, {}, {}, ResponseSettings{}, workspace, &bound);
  EXPECT_TRUE(result.clean);
  EXPECT_FALSE(result.stopped);
  EXPECT_GE(result.zone_vertices, 3);
  for (int e = 0; e < 5; ++e) {
    EXPECT_LE(strip.length_at_end(e), 2.0 * 0.1 * (1.0 + 1e-3)) << "edge " << e;
    EXPECT_FALSE(edge_over_limit(step, bound, e));
  }
  // The zone keeps its momentum: the strip's total momentum is unchanged (all masses 1).
  EXPECT_NEAR(strip.scene.momentum(strip.scene.velocity).y(), 0.5 / strip.scene.h, 1e-9 / strip.scene.h);
}

TEST(ImpactZones, WithoutABoundOrWithinTheLimitNothingMoves) {
  Strip stretched(6, [](int i) { return i == 3 ? Vec3(0.0, 0.5, 0.0) : Vec3::Zero(); });
  const Positions before = stretched.scene.x_end;
  CollisionStep step = stretched.scene.step();
  ImpactZoneWorkspace workspace;
  EXPECT_TRUE(resolve_impact_zones(step, {}, {}, ResponseSettings{}, workspace).clean);
  EXPECT_TRUE(stretched.scene.x_end == before);

  Strip calm(6, [](int i) { return Vec3(0.0, 0.01 * i, 0.0); });  // edges at ~1.005 rest
  const Positions calm_before = calm.scene.x_end;
  CollisionStep calm_step = calm.scene.step();
  const StrainBound bound{calm.rest_length, 1.0};
  const ImpactZoneResult result = resolve_impact_zones(calm_step, {}, {}, ResponseSettings{}, workspace, &bound);
  EXPECT_TRUE(result.clean);
  EXPECT_EQ(result.zone_vertices, 0);
  EXPECT_TRUE(calm.scene.x_end == calm_before);
}

TEST(ImpactZones, AnEdgeStretchedAtTheStartIsNotMadeWorse) {
  // Edge 0-1 starts at 3x its rest length (a limit of 1 cannot hold for it); the step keeps it.
  Strip strip(3, [](int) { return Vec3::Zero(); });
  strip.scene.x_start.col(0).x() = -0.2;
  strip.scene.x_end.col(0).x() = -0.2;
  CollisionStep step = strip.scene.step();
  const StrainBound bound{strip.rest_length, 1.0};
  EXPECT_FALSE(edge_over_limit(step, bound, 0));
  // Pulled further apart over the step, it is over the bound and held at its start length.
  strip.scene.x_end.col(0).x() = -0.4;
  EXPECT_TRUE(edge_over_limit(step, bound, 0));
  ImpactZoneWorkspace workspace;
  EXPECT_TRUE(resolve_impact_zones(step, {}, {}, ResponseSettings{}, workspace, &bound).clean);
  EXPECT_LE(strip.length_at_end(0), 0.3 * (1.0 + 1e-9));
}

TEST(ImpactZones, PinsMovingApartLeaveEdgesOverTheLimitWithoutStoppingWhatTheyHold) {
  // Vertex 0 pinned in place, vertex 2 pinned and pulled 0.5 m along the strip, vertex 1 free
  // between them: edges pull it into one zone with both pins, and no rigid motion follows both.
  // The result is collision-free but not clean (an edge is left over the limit); the zone motion
  // is kept (vertex 1 halfway), not stopped (which would leave edge 1-2 at 6x its rest length).
  Strip strip(3, [](int i) { return i == 2 ? Vec3(0.5, 0.0, 0.0) : Vec3::Zero(); });
  strip.scene.inverse_mass[0] = 0.0;
  strip.scene.inverse_mass[2] = 0.0;
  CollisionStep step = strip.scene.step();
  const StrainBound bound{strip.rest_length, 1.0};
  ImpactZoneWorkspace workspace;
  const ImpactZoneResult result = resolve_impact_zones(step, {}, {}, ResponseSettings{}, workspace, &bound);
  EXPECT_FALSE(result.clean);
  EXPECT_TRUE(result.collision_free);
  EXPECT_FALSE(result.stopped);
  EXPECT_EQ(result.zones, 1);
  EXPECT_NEAR(strip.scene.x_end(0, 2), 0.7, 1e-12) << "the pin keeps its motion";
  EXPECT_NEAR(strip.scene.x_end(0, 1), 0.35, 1e-9) << "halfway, with the pins' mean motion";
  EXPECT_LT(std::max(strip.length_at_end(0), strip.length_at_end(1)), 0.36);
}

TEST(ImpactZones, PinsDrivingClothThroughClothAreHeldWhereTheyMayBe) {
  // A free vertex 1 mm above a still pinned triangle; a pinned triangle 2 mm above it comes down
  // to 0.5 mm over the step. With no zone pass (straight to the fail-safe) the free vertex stops,
  // and the pins still drive the upper triangle through it. Where the pins may be held (cloth
  // pins, step.holdable) they are, and the step ends at its collision-free start; where they may
  // not (colliders) the result says it is not clean.
  for (const bool may_hold : {false, true}) {
    SCOPED_TRACE(may_hold ? "pins may be held" : "pins may not be held");
    test::CollisionScene scene;
    const Vec3 still = Vec3::Zero();
    const Vec3 down(0.0, -0.0015 / scene.h, 0.0);
    for (const Vec3& corner : {Vec3(-0.1, 0.0, -0.1), Vec3(0.1, 0.0, -0.1), Vec3(0.0, 0.0, 0.1)})
      scene.add_vertex(corner, still, 0.0);
    const int free_vertex = scene.add_vertex(Vec3(0.0, 0.001, 0.0), still, 1.0);
    for (const Vec3& corner : {Vec3(-0.1, 0.002, -0.1), Vec3(0.1, 0.002, -0.1), Vec3(0.0, 0.002, 0.1)})
      scene.add_vertex(corner, down, 0.0);
    scene.add_triangle(0, 1, 2);
    scene.add_triangle(4, 5, 6);
    CollisionStep step = scene.step();
    const std::vector<char> holdable(scene.x_start.cols(), may_hold ? 1 : 0);
    step.holdable = &holdable;
    ResponseSettings settings;
    settings.max_impact_zone_passes = 0;
    ImpactZoneWorkspace workspace;
    const ImpactZoneResult result =
        resolve_impact_zones(step, scene.all_vertex_faces(), scene.all_edge_edges(), settings, workspace);
    EXPECT_TRUE(result.stopped);
    EXPECT_EQ(result.collision_free, may_hold) << "with no strain limit, collision-free is clean";
    const bool crossed = test::segment_hits_triangle(scene.x_start.col(free_vertex), scene.x_end.col(free_vertex),
                                                     scene.x_end.col(4), scene.x_end.col(5), scene.x_end.col(6));
    if (may_hold) {
      EXPECT_TRUE(result.clean);
      EXPECT_EQ(result.held, 3);
      EXPECT_TRUE(scene.x_end == scene.x_start) << "everything at its start";
      EXPECT_TRUE(scene.velocity.isZero(1e-12));
    } else {
      EXPECT_FALSE(result.clean);
      EXPECT_EQ(result.held, 0);
      EXPECT_NEAR(scene.x_end(1, 4), 0.0005, 1e-12) << "a pin that may not be held keeps its motion";
    }
    EXPECT_FALSE(may_hold && crossed);
  }
}

TEST(ImpactZones, AFirstPassOverThePairsThatMayCollideResolvesAsTheFullOne) {
  // A vertex falling through a still triangle, and far off a second triangle with a vertex resting
  // above it. The collision phase hands the zones, when the CCD passes ended clean, only the pairs
  // with a vertex moved since (CollisionPhase::apply_impact_zones); the others are collision-free,
  // and the zones must end exactly as with every pair tested.
  const auto make_scene = [] {
    test::CollisionScene scene;
    const Vec3 still = Vec3::Zero();
    for (const Vec3& corner : {Vec3(-0.1, 0.0, -0.1), Vec3(0.1, 0.0, -0.1), Vec3(0.0, 0.0, 0.1)})
      scene.add_vertex(corner, still, 1.0);
    scene.add_vertex(Vec3(0.0, 0.01, 0.0), Vec3(0.0, -0.02 / scene.h, 0.0), 1.0);
    for (const Vec3& corner : {Vec3(4.9, 0.0, -0.1), Vec3(5.1, 0.0, -0.1), Vec3(5.0, 0.0, 0.1)})
      scene.add_vertex(corner, still, 1.0);
    scene.add_vertex(Vec3(5.0, 0.01, 0.0), still, 1.0);
    scene.add_triangle(0, 1, 2);
    scene.add_triangle(4, 5, 6);
    return scene;
  };
  test::CollisionScene full = make_scene(), restricted = make_scene();
  CollisionCandidates first_pass;
  for (const VertexFacePair& pair : restricted.all_vertex_faces()) {
    if (pair.vertex == 3 || pair.triangle == 0) first_pass.vertex_face.push_back(pair);
  }
  ASSERT_LT(first_pass.vertex_face.size(), restricted.all_vertex_faces().size());
  ImpactZoneWorkspace full_workspace, restricted_workspace;
  CollisionStep full_step = full.step(), restricted_step = restricted.step();
  const ImpactZoneResult full_result = resolve_impact_zones(
      full_step, full.all_vertex_faces(), full.all_edge_edges(), ResponseSettings{}, full_workspace);
  const ImpactZoneResult restricted_result =
      resolve_impact_zones(restricted_step, restricted.all_vertex_faces(), restricted.all_edge_edges(),
                           ResponseSettings{}, restricted_workspace, nullptr, &first_pass);
  EXPECT_TRUE(full_result.clean);
  EXPECT_GE(full_result.zone_vertices, 4) << "the falling vertex and the triangle it met became a zone";
  EXPECT_EQ(restricted_result.passes, full_result.passes);
  EXPECT_EQ(restricted_result.zone_vertices, full_result.zone_vertices);
  EXPECT_EQ(restricted_result.clean, full_result.clean);
  EXPECT_TRUE(restricted.x_end == full.x_end);
  EXPECT_TRUE(restricted.velocity == full.velocity);
}

// A strip of 12 vertices whose first vertex is a pin lifted 0.5 m over the step, the rest at rest:
// the zones grow from the pin one vertex a pass through the edges it stretches.
Strip lifted_strip() {
  Strip strip(12, [](int i) { return i == 0 ? Vec3(0.0, 0.5, 0.0) : Vec3::Zero(); });
  strip.scene.inverse_mass[0] = 0.0;
  return strip;
}

TEST(ImpactZones, WhenThePassesRunOutTheFreeVerticesArePulledToTheZones) {
  const double limit = 0.2 * (1.0 + 1e-3);  // a strain limit of 1 and the limiter's slack
  // Enough passes: the zone takes the whole strip, which follows the pin rigidly.
  {
    Strip strip = lifted_strip();
    CollisionStep step = strip.scene.step();
    const StrainBound bound{strip.rest_length, 1.0};
    ImpactZoneWorkspace workspace;
    const ImpactZoneResult result = resolve_impact_zones(step, {}, {}, ResponseSettings{}, workspace, &bound);
    EXPECT_TRUE(result.clean);
    EXPECT_FALSE(result.pulled);
    EXPECT_EQ(result.zone_vertices, 12);
    EXPECT_NEAR(strip.scene.x_end(1, 11), 0.5, 1e-12);
  }
  // Two passes: a zone of the pin and two vertices, then the pull. Every edge ends within the
  // limit, the zone follows the pin, and the far end rises less than it.
  Strip strip = lifted_strip();
  CollisionStep step = strip.scene.step();
  const StrainBound bound{strip.rest_length, 1.0};
  ResponseSettings settings;
  settings.max_impact_zone_passes = 2;
  ImpactZoneWorkspace workspace;
  const ImpactZoneResult result = resolve_impact_zones(step, {}, {}, settings, workspace, &bound);
  EXPECT_TRUE(result.clean);
  EXPECT_TRUE(result.pulled);
  EXPECT_FALSE(result.stopped);
  EXPECT_EQ(result.zone_vertices, 3);
  for (int e = 0; e < 11; ++e) {
    EXPECT_LE(strip.length_at_end(e), limit) << "edge " << e;
    EXPECT_FALSE(edge_over_limit(step, bound, e)) << "edge " << e;
  }
  for (int v = 0; v < 3; ++v) EXPECT_NEAR(strip.scene.x_end(1, v), 0.5, 1e-12) << "zone vertex " << v;
  EXPECT_GT(strip.scene.x_end(1, 3), 0.1) << "pulled up after the zone";
  EXPECT_GT(strip.scene.x_end(1, 4), 0.02) << "and the next (APullThatWouldCollideIsUndone needs it)";
  EXPECT_LT(strip.scene.x_end(1, 11), 0.4) << "the far end hangs";
  // The velocities say the same motion as the end positions.
  for (int v = 0; v < 12; ++v) {
    const Vec3 implied = (strip.scene.x_end.col(v) - strip.scene.x_start.col(v)) / strip.scene.h;
    EXPECT_TRUE(strip.scene.velocity.col(v).isApprox(implied, 1e-9)) << "vertex " << v;
  }
}

TEST(ImpactZones, APullThatWouldCollideIsUndone) {
  // The lifted strip under a still pinned triangle 1 cm above it from x = 0.31 on: the zones'
  // motion (the pin and two vertices rising at x <= 0.2, edge 2-3 sweeping x <= 0.3) clears it,
  // the pull would lift vertex 4 through it. The motion before the pull is kept: collision-free,
  // not clean, the free vertices where they were.
  Strip strip = lifted_strip();
  const int a = strip.scene.add_vertex(Vec3(0.31, 0.01, -1.0), Vec3::Zero(), 0.0);
  const int b = strip.scene.add_vertex(Vec3(2.0, 0.01, -1.0), Vec3::Zero(), 0.0);
  const int c = strip.scene.add_vertex(Vec3(0.31, 0.01, 1.0), Vec3::Zero(), 0.0);
  strip.scene.add_triangle(a, b, c);
  CollisionStep step = strip.scene.step();
  const StrainBound bound{strip.rest_length, 1.0};
  ResponseSettings settings;
  settings.max_impact_zone_passes = 2;
  ImpactZoneWorkspace workspace;
  const ImpactZoneResult result = resolve_impact_zones(
      step, strip.scene.all_vertex_faces(), strip.scene.all_edge_edges(), settings, workspace, &bound);
  EXPECT_FALSE(result.pulled);
  EXPECT_FALSE(result.clean);
  EXPECT_TRUE(result.collision_free);
  EXPECT_FALSE(result.stopped);
  for (int v = 3; v < 12; ++v) {
    EXPECT_TRUE(strip.scene.x_end.col(v) == strip.scene.x_start.col(v)) << "vertex " << v;
    EXPECT_TRUE(strip.scene.velocity.col(v).isZero()) << "vertex " << v;
  }
  EXPECT_GT(strip.length_at_end(2), 0.4) << "edge 2-3 stays over the limit";
}

}  // namespace
}  // namespace weft
