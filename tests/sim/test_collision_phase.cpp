// The World's collision phase on tiny inline scenes: a cloth thrown at a thin box much faster
// than one step can resolve, two cloths crossing, a kinematic collider lifting a cloth, self-
// collision on and off, and the contact records and stats the viewer and recordings read.
#include <gtest/gtest.h>

#include <fstream>

#include "check/intersection_check.hpp"
#include "core/topology.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "support/scene_invariants.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

using nlohmann::json;

World world_of(const std::string& text) { return build_world(parse_scene(json::parse(text), "inline")); }

void run(World& world, int steps, const testing::SceneInvariants& invariants) {
  for (int k = 0; k < steps; ++k) {
    world.step();
    const testing::InvariantReport report = invariants.check(world);
    ASSERT_TRUE(report.ok()) << "step " << k << ": " << report.first;
  }
}

TEST(CollisionPhase, AClothThrownFasterThanAStepStopsOnAThinBox) {
  // 30 m/s with h = 1/100: 30 cm per step against a 2 mm box, so proximity alone never sees it.
  World world = world_of(R"({
    "solver": {"integrator": "symplectic_euler", "time_step": 0.01},
    "cloths": [{"grid": {"size": [0.4, 0.4], "resolution": [6, 6]}, "initial_velocity": [0, -30, 0],
                "transform": {"translation": [0, 0.2, 0], "rotation_degrees": [-90, 0, 0]},
                "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}}}],
    "colliders": [{"type": "box", "center": [0, 0, 0], "half_extents": [1, 0.001, 1]}]
  })");
  const testing::SceneInvariants invariants(world);
  StepStats totals;
  for (int k = 0; k < 5; ++k) {
    run(world, 1, invariants);
    totals += world.last_step_stats();
  }
  EXPECT_GT(world.cloths()[0].state.x.row(1).minCoeff(), 0.001);
  EXPECT_GT(totals.collision.vertex_face_candidates,
            0);  // the box was seen (self pairs of the flat sheet are culled)
  EXPECT_TRUE(world.last_step_stats().collision.clean);
}

// stats.csv's collision_correction_max and collision_corrected_vertices: the thrown cloth's first
// step has symplectic Euler put every vertex at y0 + h (v0 - h g) = -0.100981 (the sheet is at
// rest, so its springs pull nothing), through the box; the phase stops it above. A sheet falling
// in free space is left where the integrator put it.
TEST(CollisionPhase, CorrectionsMeasureHowFarTheResponseMovedTheIntegratorsMotion) {
  const std::string cloth = R"("cloths": [{"grid": {"size": [0.4, 0.4], "resolution": [6, 6]},
      "initial_velocity": [0, -30, 0], "transform": {"translation": [0, 0.2, 0], "rotation_degrees": [-90, 0, 0]},
      "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                  "bend": {"stiffness": 0, "damping": 0}}}])";
  const std::string solver = R"("solver": {"integrator": "symplectic_euler", "time_step": 0.01}, "fps": 100)";
  World thrown = world_of("{" + solver + "," + cloth +
                          R"(, "colliders": [{"type": "box", "center": [0, 0, 0], "half_extents": [1, 0.001, 1]}]})");
  const Positions start = thrown.cloths()[0].state.x;
  thrown.step();
  const Positions& end = thrown.cloths()[0].state.x;
  double largest = 0.0;
  int moved = 0;
  for (Eigen::Index i = 0; i < start.cols(); ++i) {
    Vec3 integrated = start.col(i);
    integrated.y() += 0.01 * (-30.0 - 0.01 * 9.81);
    const double correction = (end.col(i) - integrated).norm();
    largest = std::max(largest, correction);
    moved += correction > 0.01 * thrown.cloths()[0].model.thickness ? 1 : 0;
  }
  ASSERT_GT(end.row(1).minCoeff(), 0.001) << "stopped on the box";
  EXPECT_GT(largest, 0.1);
  EXPECT_NEAR(thrown.last_step_stats().collision.largest_correction, largest, 1e-12);
  EXPECT_EQ(thrown.last_step_stats().collision.corrected_vertices, moved);
  EXPECT_EQ(moved, start.cols());

  World falling = world_of("{" + solver + "," + cloth + "}");
  for (int k = 0; k < 3; ++k) falling.step();
  EXPECT_EQ(falling.last_step_stats().collision.largest_correction, 0.0);
  EXPECT_EQ(falling.last_step_stats().collision.corrected_vertices, 0);
}

// Largest |x_j - x_i| / rest - 1 over the cloth's edges.
double largest_edge_strain(const Cloth& cloth) {
  const MeshTopology topology = build_topology(cloth.model.triangles, static_cast<int>(cloth.state.x.cols()));
  double largest = 0.0;
  for (int e = 0; e < topology.num_edges(); ++e) {
    const int i = topology.edges(0, e);
    const int j = topology.edges(1, e);
    const double rest = (cloth.model.rest_positions.col(j) - cloth.model.rest_positions.col(i)).norm();
    largest = std::max(largest, (cloth.state.x.col(j) - cloth.state.x.col(i)).norm() / rest - 1.0);
  }
  return largest;
}

TEST(CollisionPhase, StrainLimitBoundsTheStretchTheImpulsesLeave) {
  // The middle strip of a cloth thrown at 30 m/s stops on a narrow thin box while the sides fly
  // on by 30 cm a step: the edges over the box's rims stretch several times, unless limited.
  const auto scene_with_limit = [](double limit) {
    return R"({
      "solver": {"integrator": "symplectic_euler", "time_step": 0.01},
      "collision": {"strain_limit": )" +
           std::to_string(limit) + R"(},
      "cloths": [{"grid": {"size": [0.4, 0.4], "resolution": [6, 6]}, "initial_velocity": [0, -30, 0],
                  "transform": {"translation": [0, 0.2, 0], "rotation_degrees": [-90, 0, 0]},
                  "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                              "bend": {"stiffness": 0, "damping": 0}}}],
      "colliders": [{"type": "box", "center": [0, 0, 0], "half_extents": [0.1, 0.001, 1]}]
    })";
  };
  World free = world_of(scene_with_limit(0.0));
  World limited = world_of(scene_with_limit(0.2));
  const testing::SceneInvariants free_invariants(free);
  const testing::SceneInvariants limited_invariants(limited);
  double free_strain = 0.0;
  int corrections = 0;
  for (int k = 0; k < 3; ++k) {
    run(free, 1, free_invariants);
    run(limited, 1, limited_invariants);
    free_strain = std::max(free_strain, largest_edge_strain(free.cloths()[0]));
    EXPECT_LE(largest_edge_strain(limited.cloths()[0]), 1.2 * (1.0 + 1e-3) - 1.0 + 1e-12) << "step " << k;
    EXPECT_TRUE(limited.last_step_stats().collision.clean) << "step " << k;
    corrections += limited.last_step_stats().collision.strain_limited_edges;
  }
  EXPECT_GT(free_strain, 1.0) << "the scene must stretch the cloth for the limit to matter";
  EXPECT_GT(corrections, 0);
}

TEST(CollisionPhase, RecordsSayWhatTouchedWhat) {
  World world = world_of(R"({
    "solver": {"integrator": "symplectic_euler", "time_step": 0.01},
    "cloths": [{"grid": {"size": [0.4, 0.4], "resolution": [5, 5]}, "initial_velocity": [0, -3, 0],
                "transform": {"translation": [0, 0.02, 0], "rotation_degrees": [-90, 0, 0]}, "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}}}],
    "colliders": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]
  })");
  world.step();
  ASSERT_FALSE(world.contacts().empty());
  const StepStats& stats = world.last_step_stats();
  EXPECT_EQ(stats.contacts, static_cast<int>(world.contacts().size()));
  EXPECT_EQ(stats.contacts, stats.collision.proximity_contacts + stats.collision.ccd_impulses);
  for (const ContactRecord& record : world.contacts()) {
    EXPECT_EQ(record.partners, ContactPartners::cloth_solid);
    EXPECT_GT(record.impulse, 0.0);
    EXPECT_LT(std::abs(record.position.y()), 0.03);
  }
  EXPECT_GE(stats.collision.broad_ms + stats.collision.narrow_ms + stats.collision.response_ms, 0.0);
  EXPECT_LE(stats.collision.broad_ms + stats.collision.narrow_ms + stats.collision.response_ms,
            stats.collisions_ms + 1e-9);
  // Every vertex stays above the plane, and none moves down any more.
  for (int i = 0; i < world.cloths()[0].num_vertices(); ++i) {
    EXPECT_GT(world.cloths()[0].state.x(1, i), 0.0);
    EXPECT_GT(world.cloths()[0].state.v(1, i), -1e-9);
  }
}

TEST(CollisionPhase, TwoClothsCrossingAtSpeedDoNotPassThrough) {
  World world = world_of(R"({
    "gravity": [0, 0, 0],
    "solver": {"integrator": "symplectic_euler", "time_step": 0.005},
    "cloths": [
      {"grid": {"size": [0.5, 0.5], "resolution": [8, 8]}, "initial_velocity": [0, -8, 0],
       "transform": {"translation": [0, 0.05, 0], "rotation_degrees": [-90, 0, 0]}, "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}}},
      {"grid": {"size": [0.5, 0.5], "resolution": [7, 7]}, "initial_velocity": [0, 8, 0],
       "transform": {"translation": [0.03, -0.05, 0.02], "rotation_degrees": [-90, 20, 0]}, "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}}}
    ]
  })");
  const testing::SceneInvariants invariants(world);
  bool cloth_cloth = false;
  for (int k = 0; k < 10; ++k) {
    run(world, 1, invariants);
    for (const ContactRecord& record : world.contacts()) cloth_cloth |= record.partners == ContactPartners::cloth_cloth;
  }
  EXPECT_TRUE(cloth_cloth);
  // The first cloth is still above the second in the middle.
  const Vec3 upper = world.cloths()[0].state.x.rowwise().mean();
  const Vec3 lower = world.cloths()[1].state.x.rowwise().mean();
  EXPECT_GT(upper.y(), lower.y());
}

TEST(CollisionPhase, AKinematicColliderLiftsTheCloth) {
  World world = world_of(R"({
    "solver": {"integrator": "symplectic_euler", "time_step": 0.005},
    "cloths": [{"grid": {"size": [0.3, 0.3], "resolution": [6, 6]},
                "transform": {"translation": [0, 0.01, 0], "rotation_degrees": [-90, 0, 0]}, "springs": {"structural": {"stiffness": 10, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}}}],
    "colliders": [{"type": "box", "center": [0, -0.1, 0], "half_extents": [0.5, 0.1, 0.5],
                   "motion": {"velocity": [0, 1, 0]}}]
  })");
  const testing::SceneInvariants invariants(world);
  run(world, 40, invariants);  // about 0.2 s: the box top rises from 0 to 1 m/s times that
  const double top = world.time();
  EXPECT_NEAR(world.collider_positions(0).row(1).maxCoeff(), top, 1e-12);
  EXPECT_GT(world.cloths()[0].state.x.row(1).minCoeff(), top);
  EXPECT_LT(world.cloths()[0].state.x.row(1).maxCoeff(), top + 0.02) << "carried, not thrown";
}

TEST(CollisionPhase, AColliderDrivenThroughPinnedClothIsNotReportedClean) {
  // Every vertex of the cloth is pinned, so no response can move anything in the collider's way:
  // the pairs are left out of the response, but the step in which the box's top crosses the
  // cloth, and each step its sides cut through it, must not claim to be clean.
  std::string pins = "[0";
  for (int v = 1; v < 16; ++v) pins += ", " + std::to_string(v);
  pins += "]";
  World world = world_of(R"({
    "gravity": [0, 0, 0],
    "solver": {"integrator": "symplectic_euler", "time_step": 0.005},
    "cloths": [{"grid": {"size": [0.4, 0.4], "resolution": [4, 4]},
                "transform": {"rotation_degrees": [-90, 0, 0]}, "pins": {"vertices": )" +
                         pins + R"(}}],
    "colliders": [{"type": "box", "center": [0.01, -0.08, 0.02], "half_extents": [0.1, 0.05, 0.1],
                   "motion": {"velocity": [0, 1, 0]}}]
  })");
  const Positions start = world.cloths()[0].state.x;
  std::vector<int> unclean_steps;
  for (int k = 0; k < 30; ++k) {  // the top reaches the cloth in step 6, the bottom leaves it in step 26
    world.step();
    if (!world.last_step_stats().collision.clean) unclean_steps.push_back(k);
  }
  EXPECT_TRUE(world.cloths()[0].state.x == start) << "pins stay where they are";
  ASSERT_FALSE(unclean_steps.empty());
  EXPECT_GE(unclean_steps.front(), 5) << "clean before the box arrives";
  EXPECT_LE(unclean_steps.back(), 27) << "clean after it has passed";
  EXPECT_GE(unclean_steps.size(), 10u) << "the box's sides cut the cloth while it passes";
}

// One cloth made of two parallel sheets in one mesh, driven into each other: with self-collision
// they stop, without it they pass through.
TEST(CollisionPhase, SelfCollisionCanBeTurnedOff) {
  testing::TempDir dir;
  {
    std::ofstream obj(dir.file("sheets.obj"));
    for (double y : {0.02, -0.02}) {
      obj << "v -0.1 " << y << " -0.1\nv 0.1 " << y << " -0.1\nv 0.1 " << y << " 0.1\nv -0.1 " << y << " 0.1\n";
    }
    obj << "f 1 3 2\nf 1 4 3\nf 5 7 6\nf 5 8 7\n";
  }
  for (bool self_collision : {true, false}) {
    json scene = {{"gravity", {0, 0, 0}},
                  {"solver", {{"integrator", "symplectic_euler"}, {"time_step", 0.005}}},
                  {"cloths", {{{"obj", "sheets.obj"},
                               {"springs", {{"structural", {{"stiffness", 0}, {"damping", 0}}},
                                            {"bend", {{"stiffness", 0}, {"damping", 0}}}}},
                               {"self_collision", self_collision}}}}};
    World world = build_world(parse_scene(scene, dir.file("scene.json")));
    Cloth& cloth = world.cloths()[0];
    for (int i = 0; i < 4; ++i) cloth.state.v.col(i) = Vec3(0, -2, 0);
    for (int i = 4; i < 8; ++i) cloth.state.v.col(i) = Vec3(0, 2, 0);
    for (int k = 0; k < 10; ++k) world.step();  // 0.05 s: 0.2 m of closing, 4 cm apart
    const double upper = cloth.state.x.row(1).head(4).mean();
    const double lower = cloth.state.x.row(1).tail(4).mean();
    if (self_collision) {
      EXPECT_GT(upper, lower);
      EXPECT_TRUE(find_triangle_intersections(cloth.state.x, cloth.model.triangles).empty());
    } else {
      EXPECT_LT(upper, lower) << "the sheets passed through each other";
    }
  }
}

}  // namespace
}  // namespace weft
