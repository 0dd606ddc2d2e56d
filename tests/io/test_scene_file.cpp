// Scene files: every error class names the file and the JSON path; overrides; round trip.
#include "io/scene_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/scene_builder.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

using nlohmann::json;

const char* minimal_scene = R"({
  "name": "test",
  "solver": {"time_step": 0.001},
  "cloths": [{"grid": {"size": [1, 1], "resolution": [4, 4]}}],
  "colliders": [{"type": "sphere", "center": [0, -1, 0], "radius": 0.5}]
})";

// Parses `text` after applying `overrides`, expecting a SceneError at `path` whose message contains `words`.
void expect_scene_error(const std::string& text, const std::vector<std::string>& overrides,
                        const std::string& path, const std::string& words) {
  json document = json::parse(text);
  std::string file;  // what the error must name: the override being applied, else the scene
  try {
    for (const auto& assignment : overrides) {
      file = "--set " + assignment;
      apply_override(document, assignment);
    }
    file = "scene.json";
    const SceneDesc scene = parse_scene(document, "scene.json");
    build_world(scene);
    FAIL() << "expected a SceneError at " << path;
  } catch (const SceneError& error) {
    EXPECT_EQ(error.file(), file);
    EXPECT_EQ(error.json_path(), path) << error.what();
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).rfind(printable_text(file + ": " + path), 0), 0u) << error.what();
  }
}

TEST(SceneFile, MinimalSceneTakesDefaultsFromTheStructs) {
  const SceneDesc scene = parse_scene(json::parse(minimal_scene), "scene.json");
  const SceneDesc defaults;
  const ClothDesc cloth_defaults;
  EXPECT_EQ(scene.name, "test");
  EXPECT_DOUBLE_EQ(scene.time_step, 0.001);
  EXPECT_EQ(scene.substeps, defaults.substeps);
  EXPECT_EQ(scene.fps, defaults.fps);
  ASSERT_EQ(scene.cloths.size(), 1u);
  EXPECT_EQ(scene.cloths[0].grid_nx, 4);
  EXPECT_DOUBLE_EQ(scene.cloths[0].density, cloth_defaults.density);
  EXPECT_DOUBLE_EQ(scene.cloths[0].structural.stiffness, cloth_defaults.structural.stiffness);
  ASSERT_EQ(scene.colliders.size(), 1u);
  EXPECT_EQ(scene.colliders[0].shape, ColliderShape::sphere);
  EXPECT_DOUBLE_EQ(scene.colliders[0].radius, 0.5);
}

TEST(SceneFile, UnknownKeysAreRejectedAtEveryLevel) {
  expect_scene_error(minimal_scene, {"colour=1"}, "/colour", "unknown key \"colour\"");
  expect_scene_error(minimal_scene, {"solver.timestep=0.1"}, "/solver/timestep", "unknown key");
  expect_scene_error(minimal_scene, {"cloths.0.grid.rows=3"}, "/cloths/0/grid/rows", "unknown key");
  expect_scene_error(minimal_scene, {"colliders.0.half_extents=[1,1,1]"}, "/colliders/0/half_extents",
                     "unknown key");
}

TEST(SceneFile, WrongTypesNameWhatWasExpected) {
  expect_scene_error(minimal_scene, {"solver.time_step=\"fast\""}, "/solver/time_step", "expected a number > 0");
  expect_scene_error(minimal_scene, {"gravity=[0,-9.81]"}, "/gravity", "expected an array of 3 numbers");
  expect_scene_error(minimal_scene, {"cloths.0.grid.resolution=[4,4.5]"}, "/cloths/0/grid/resolution/1",
                     "expected an integer");
  expect_scene_error(minimal_scene, {"solver.integrator=runge_kutta"}, "/solver/integrator",
                     "expected one of \"symplectic_euler\", \"midpoint_euler_cromer\", \"explicit_midpoint\", \"implicit_euler\"");
  expect_scene_error(minimal_scene, {"cloths={}"}, "/cloths", "expected an array of cloths");
  expect_scene_error(minimal_scene, {"colliders.0.type=cone"}, "/colliders/0/type", "expected one of");
  expect_scene_error(minimal_scene, {R"(cloths.0.bending={"model": "cubic"})"}, "/cloths/0/bending/model",
                     "expected one of \"dihedral\", \"quadratic\"");
  expect_scene_error(minimal_scene,
                     {R"(cloths.0={"sphere": {"radius": 0.2, "slices": 12, "stacks": 6}, "bending": {"model": "quadratic"}})"},
                     "/cloths/0/bending/model", "needs a flat rest mesh");
}

TEST(SceneFile, OutOfRangeValuesAreRejected) {
  expect_scene_error(minimal_scene, {"solver.time_step=0"}, "/solver/time_step", "expected a number > 0");
  expect_scene_error(minimal_scene, {"solver.time_step=-0.01"}, "/solver/time_step", "> 0");
  expect_scene_error(minimal_scene, {"cloths.0.mass=-1"}, "/cloths/0/mass", "expected a number >= 0");
  expect_scene_error(minimal_scene, {"cloths.0.density=0"}, "/cloths/0/density", "> 0");
  expect_scene_error(minimal_scene, {"cloths.0.grid.resolution=[1,4]"}, "/cloths/0/grid/resolution/0",
                     "expected an integer in [2, 4096]");
  expect_scene_error(minimal_scene, {"fps=0"}, "/fps", "in [1, 10000]");
  expect_scene_error(minimal_scene, {"fps=1e300"}, "/fps", "in [1, 10000]");
  expect_scene_error(minimal_scene, {"frames=-3"}, "/frames", "expected an integer in [0,");
  expect_scene_error(minimal_scene, {"colliders.0.radius=0"}, "/colliders/0/radius", "> 0");
  expect_scene_error(minimal_scene, {"cloths.0.springs.bend.stiffness=-5"}, "/cloths/0/springs/bend/stiffness",
                     ">= 0");
  expect_scene_error(minimal_scene, {"cloths.0.pins.vertices=[0,16]"}, "/cloths/0/pins/vertices/1",
                     "expected a vertex index below 16, got 16");
  expect_scene_error(minimal_scene, {"cloths.0.pins.corners=[\"middle\"]"}, "/cloths/0/pins/corners/0",
                     "expected one of");
}

TEST(SceneFile, ANewtonToleranceThatTheRestingStartMeetsIsRefused) {
  // At h = 1/240 gravity adds 9.81 / 240 = 0.0409 m/s a step, the residual of Newton's start;
  // a tolerance at or above it would freeze the drape (every step "converged" at the start; with
  // the one iteration every step takes, such a tolerance stops after it).
  const std::vector<std::string> implicit = {"solver.integrator=\"implicit_euler\"",
                                             "solver.time_step=0.004166666666666667"};
  auto with = [&](const std::string& more) {
    std::vector<std::string> overrides = implicit;
    overrides.push_back(more);
    return overrides;
  };
  expect_scene_error(minimal_scene, with("solver.newton.tolerance=0.05"), "/solver/newton/tolerance",
                     "expected a tolerance below 0.04088 m/s");
  // Substeps shorten the step the solve takes.
  std::vector<std::string> substeps = with("solver.newton.tolerance=0.03");
  substeps.push_back("solver.substeps=2");
  expect_scene_error(minimal_scene, substeps, "/solver/newton/tolerance", "below 0.02044 m/s");
  // Below it, or without gravity, or with an integrator that has no Newton solve, it parses.
  json document = json::parse(minimal_scene);
  for (const auto& assignment : with("solver.newton.tolerance=0.03")) apply_override(document, assignment);
  EXPECT_NO_THROW(parse_scene(document, "s"));
  apply_override(document, "solver.newton.tolerance=0.05");
  apply_override(document, "gravity=[0,0,0]");
  EXPECT_NO_THROW(parse_scene(document, "s"));
  apply_override(document, "gravity=[0,-9.81,0]");
  apply_override(document, "solver.integrator=\"xpbd\"");
  EXPECT_NO_THROW(parse_scene(document, "s"));
}

TEST(SceneFile, XpbdKeysAreReadCheckedAndRoundTrip) {
  json document = json::parse(minimal_scene);
  apply_override(document, "solver.integrator=xpbd");
  apply_override(document, "solver.xpbd={\"substeps\": 12, \"iterations\": 3}");
  const SceneDesc scene = parse_scene(document, "scene.json");
  EXPECT_EQ(scene.integrator, IntegratorKind::xpbd);
  EXPECT_EQ(scene.xpbd.substeps, 12);
  EXPECT_EQ(scene.xpbd.iterations, 3);
  const World world = build_world(scene);
  EXPECT_EQ(world.settings.xpbd.substeps, 12);
  const SceneDesc again = parse_scene(scene_to_json(scene), "scene.json");
  EXPECT_EQ(again.xpbd.substeps, 12);
  EXPECT_EQ(again.xpbd.iterations, 3);
  expect_scene_error(minimal_scene, {"solver.xpbd.substeps=0"}, "/solver/xpbd/substeps", "expected an integer in [1,");
  expect_scene_error(minimal_scene, {"solver.xpbd.iterations=1.5"}, "/solver/xpbd/iterations", "expected an integer");
  expect_scene_error(minimal_scene, {"solver.xpbd.sweeps=2"}, "/solver/xpbd/sweeps", "unknown");
}

TEST(SceneFile, NonFiniteNumbersAreRejected) {
  // JSON has no NaN literal: "nan" on the command line arrives as a string, 1e999 overflows to infinity.
  expect_scene_error(minimal_scene, {"solver.time_step=nan"}, "/solver/time_step", "expected a number > 0");
  json document = json::parse(minimal_scene);
  document["cloths"][0]["thickness"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(parse_scene(document, "scene.json"), SceneError);
  document = json::parse(minimal_scene);
  document["gravity"] = {0.0, std::numeric_limits<double>::infinity(), 0.0};
  try {
    parse_scene(document, "scene.json");
    FAIL() << "infinite gravity accepted";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.json_path(), "/gravity/1");
    EXPECT_NE(std::string(error.what()).find("finite"), std::string::npos) << error.what();
  }
}

TEST(SceneFile, FramesNeedingMoreThanTheBoundOfSubStepsAreRefused) {
  // 30 fps at h = 0.001 is 34 steps a frame.
  expect_scene_error(
      minimal_scene, {"solver.time_step=1e-12"}, "/solver/time_step",
      "expected a time step of at least 3.333e-08 s at 30 fps, got 1e-12: 3.333e+10 sub-steps");
  expect_scene_error(minimal_scene, {"solver.substeps=100000"}, "/solver/substeps",
                     "expected at most 29411 substeps with 34 steps per frame, got 100000");
  expect_scene_error(minimal_scene,
                     {"solver.integrator=xpbd", "solver.substeps=100", "solver.xpbd.substeps=1000"},
                     "/solver/xpbd/substeps", "expected at most 294 XPBD substeps with 3400 steps per frame");
  // Just under the bound: accepted.
  json document = json::parse(minimal_scene);
  apply_override(document, "fps=1");
  apply_override(document, "solver.time_step=1.000001e-6");
  EXPECT_NO_THROW(parse_scene(document, "scene.json"));
}

TEST(SceneFile, ContactThicknessBeyondATenthOfTheClothIsRefused) {
  // The 1 x 1 m cloth's diagonal is 1.414 m.
  json document = json::parse(minimal_scene);
  apply_override(document, "cloths.0.thickness=0.14");
  EXPECT_NO_THROW(build_world(parse_scene(document, "scene.json")));
  expect_scene_error(minimal_scene, {"cloths.0.thickness=0.15"}, "/cloths/0/thickness",
                     "expected a contact thickness of at most 0.1414 m (10% of the cloth's size");
}

TEST(SceneFile, MissingObjFileNamesTheObjField) {
  expect_scene_error(R"({"cloths": [{"obj": "no_such_mesh.obj"}]})", {}, "/cloths/0/obj", "no_such_mesh.obj");
  expect_scene_error(R"({"cloths": [{"obj": "x.obj", "grid": {}}]})", {}, "/cloths/0", "not several");
  expect_scene_error(R"({"cloths": [{"obj": "x.obj", "pins": {"corners": ["top_left"]}}]})", {},
                     "/cloths/0/pins/corners", "only on grid cloths");
}

TEST(SceneFile, BadOverridesAreReported) {
  expect_scene_error(minimal_scene, {"cloths.3.name=x"}, "/cloths/3", "expected an index below 1");
  expect_scene_error(minimal_scene, {"name.first=x"}, "/name", "cannot descend");
  json document = json::parse(minimal_scene);
  EXPECT_THROW(apply_override(document, "no_equals_sign"), SceneError);
}

// Found by tests/fuzz/fuzz_set: an index past std::stoul's range (std::out_of_range) and a bare
// value that is not UTF-8 (nlohmann's type_error when written into a message) are SceneErrors.
TEST(SceneFile, OverridesWithHugeIndicesOrNonUtf8ValuesAreSceneErrors) {
  expect_scene_error(minimal_scene, {"cloths.99999999999999999999.name=x"}, "/cloths/99999999999999999999",
                     "expected an index below 1");
  expect_scene_error(minimal_scene, {"solver.xpbd.iterations=\xb4"}, "", "neither JSON nor UTF-8 text");
  expect_scene_error(minimal_scene, {"name=caf\xc3"}, "", "neither JSON nor UTF-8 text");
  // Valid UTF-8 stays a bare string.
  json document = json::parse(minimal_scene);
  apply_override(document, "name=caf\xc3\xa9");
  EXPECT_EQ(parse_scene(document, "scene.json").name, "caf\xc3\xa9");
}

// parse_scene_text, as weft reads a scene: an error inside what an override wrote names the
// override, one elsewhere the scene file.
TEST(SceneFile, ErrorsInsideAnOverrideNameTheOverride) {
  const auto message = [](const std::string& text, const std::vector<std::string>& overrides) -> std::string {
    try {
      parse_scene_text(text, "scene.json", overrides);
    } catch (const SceneError& error) {
      return error.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(minimal_scene, {"solver.timestep=0.001"})
                .rfind("--set solver.timestep=0.001: /solver/timestep: unknown key \"timestep\"", 0),
            0u);
  EXPECT_EQ(message(minimal_scene, {"fps=30", "solver.time_step=-1"})
                .rfind("--set solver.time_step=-1: /solver/time_step: expected a number > 0", 0),
            0u);
  // A member the override created holds the error: the override made /extra, not the file.
  EXPECT_EQ(message(minimal_scene, {"extra.depth=1"}).rfind("--set extra.depth=1: /extra: unknown key", 0),
            0u);
  EXPECT_EQ(message(minimal_scene, {"cloths.0.grid.resolution=[4,4.5]"})
                .rfind("--set cloths.0.grid.resolution=[4,4.5]: /cloths/0/grid/resolution/1: ", 0),
            0u);
  // The later of two overrides of one field is the one in effect, and the one named.
  EXPECT_EQ(message(minimal_scene, {"fps=-1", "fps=0"}).rfind("--set fps=0: /fps: ", 0), 0u);
  // An error in the file stays the file's, whatever else is overridden.
  std::string bad_file = minimal_scene;
  bad_file.insert(bad_file.find('{') + 1, R"("colour": 1,)");
  EXPECT_EQ(message(bad_file, {"fps=30"}).rfind("scene.json: /colour: unknown key", 0), 0u);
}

TEST(SceneFile, OverridesAcceptDotsPointersJsonAndBareStrings) {
  json document = json::parse(minimal_scene);
  apply_override(document, "solver.substeps=4");
  apply_override(document, "/cloths/0/grid/resolution=[8, 6]");
  apply_override(document, "name=sweep_case_1");
  apply_override(document, "solver.integrator=symplectic_euler");
  const SceneDesc scene = parse_scene(document, "scene.json");
  EXPECT_EQ(scene.substeps, 4);
  EXPECT_EQ(scene.cloths[0].grid_nx, 8);
  EXPECT_EQ(scene.cloths[0].grid_ny, 6);
  EXPECT_EQ(scene.name, "sweep_case_1");
}

// Found by tests/fuzz/fuzz_scene: a number past a double's range made nlohmann's parser throw
// out_of_range, which escaped load_scene_file (weft aborted, exit 134).
TEST(SceneFile, NumbersPastADoublesRangeAreInvalidJson) {
  testing::TempDir dir;
  const std::string path = dir.file("huge.json");
  std::ofstream(path) << R"({"name": "x", "fps": 1e400})";
  try {
    load_scene_file(path);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.json_path(), "");
    EXPECT_NE(std::string(error.what()).find("huge.json: /: invalid JSON: number overflow parsing '1e400'"),
              std::string::npos)
        << error.what();
  }
}

TEST(SceneFile, ResolvedSceneRoundTrips) {
  json document = json::parse(minimal_scene);
  apply_override(document, "cloths.0.pins.corners=[\"top_left\"]");
  const SceneDesc scene = parse_scene(document, "scene.json");
  const json written = scene_to_json(scene);
  const SceneDesc again = parse_scene(written, "scene.json");
  EXPECT_EQ(scene_to_json(again), written);
  EXPECT_EQ(again.cloths[0].pins.corners, std::vector<std::string>{"top_left"});
}

TEST(SceneFile, FileErrorsNameTheFile) {
  testing::TempDir dir;
  try {
    load_scene_file(dir.file("missing.json"));
    FAIL();
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("missing.json"), std::string::npos);
  }
  const std::string broken = dir.file("broken.json");
  std::ofstream(broken) << "{\n  \"name\": \"x\",\n  \"fps\": \n}\n";
  try {
    load_scene_file(broken);
    FAIL();
  } catch (const SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("broken.json"), std::string::npos) << message;
    EXPECT_NE(message.find("line 4"), std::string::npos) << message;
  }
}

TEST(SceneFile, ShippedScenesLoadAndBuild) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(WEFT_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".json") continue;
    const SceneDesc scene = load_scene_file(entry.path().string());
    const World world = build_world(scene);
    EXPECT_GE(world.cloths().size(), 1u) << entry.path();
    ++scenes;
  }
  EXPECT_GE(scenes, 10);
}

TEST(SceneFile, ViewIsReadCheckedAndRoundTrips) {
  json document = json::parse(minimal_scene);
  document["view"] = json::parse(R"({"target": [0, 0.5, 0], "distance": 3, "yaw_degrees": -30,
    "pitch_degrees": 40, "show": ["cutaway", "no-contacts"], "impulse_scale": 20, "max_arrow_length": 0.05})");
  const SceneDesc scene = parse_scene(document, "scene.json");
  EXPECT_TRUE(scene.view.has_target);
  EXPECT_EQ(scene.view.target, Vec3(0.0, 0.5, 0.0));
  EXPECT_DOUBLE_EQ(scene.view.distance, 3.0);
  EXPECT_DOUBLE_EQ(scene.view.yaw_degrees, -30.0);
  EXPECT_DOUBLE_EQ(scene.view.pitch_degrees, 40.0);
  EXPECT_EQ(scene.view.show, (std::vector<std::string>{"cutaway", "no-contacts"}));
  EXPECT_DOUBLE_EQ(scene.view.impulse_scale, 20.0);
  EXPECT_DOUBLE_EQ(scene.view.max_arrow_length, 0.05);
  const json written = scene_to_json(scene);
  EXPECT_EQ(scene_to_json(parse_scene(written, "scene.json")), written);

  // Without a view, the camera frames the whole scene: no target, no distance.
  const SceneDesc plain = parse_scene(json::parse(minimal_scene), "scene.json");
  EXPECT_FALSE(plain.view.has_target);
  EXPECT_EQ(plain.view.distance, 0.0);
  EXPECT_TRUE(plain.view.show.empty());
  EXPECT_FALSE(parse_scene(scene_to_json(plain), "scene.json").view.has_target);
}

TEST(SceneFile, ViewErrorsNameThePath) {
  expect_scene_error(minimal_scene, {"view.zoom=2"}, "/view/zoom", "unknown key \"zoom\"");
  expect_scene_error(minimal_scene, {"view=[1,2]"}, "/view", "expected an object");
  expect_scene_error(minimal_scene, {"view.target=[0,1]"}, "/view/target", "expected an array of 3 numbers");
  expect_scene_error(minimal_scene, {"view.distance=0"}, "/view/distance", "expected a number > 0");
  expect_scene_error(minimal_scene, {"view.pitch_degrees=90"}, "/view/pitch_degrees", "in [-88, 88]");
  expect_scene_error(minimal_scene, {"view.yaw_degrees=\"left\""}, "/view/yaw_degrees", "expected a number");
  expect_scene_error(minimal_scene, {"view.show=[\"cutaway\",\"aabb\"]"}, "/view/show/1",
                     "expected one of \"boxes\"");
  expect_scene_error(minimal_scene, {"view.show=\"cutaway\""}, "/view/show", "expected an array of strings");
  expect_scene_error(minimal_scene, {"view.impulse_scale=-1"}, "/view/impulse_scale", "> 0");
  expect_scene_error(minimal_scene, {"view.max_arrow_length=2"}, "/view/max_arrow_length", "in (0, 1]");
}

TEST(SceneFile, ViewIsNotPartOfTheSimulatedScene) {
  json document = json::parse(minimal_scene);
  const json plain = scene_to_json(parse_scene(document, "scene.json"));
  apply_override(document, "view.show=[\"cutaway\"]");
  apply_override(document, "view.distance=4");
  const json viewed = scene_to_json(parse_scene(document, "scene.json"));
  EXPECT_NE(viewed, plain);
  EXPECT_EQ(simulated_part(viewed), simulated_part(plain));
  // Any other change still shows.
  apply_override(document, "fps=60");
  EXPECT_NE(simulated_part(scene_to_json(parse_scene(document, "scene.json"))), simulated_part(plain));
}

const char* collision_scene = R"({
  "collision": {"repulsion_stiffness": 500, "max_ccd_passes": 4, "max_rounds": 2, "strain_limit": 0.5,
                "strain_limit_sweeps": 8},
  "cloths": [{"grid": {"size": [1, 1], "resolution": [4, 4]}, "thickness": 0.004,
              "friction": {"static": 0.6, "kinetic": 0.5}, "self_collision": false,
              "initial_velocity": [0, -2, 0]}],
  "colliders": [
    {"type": "capsule", "center": [0, -1, 0], "axis": [1, 0, 0], "radius": 0.2, "half_length": 0.4,
     "friction": 0.2, "static_friction": 0.25},
    {"type": "cylinder", "center": [0, 0, 0], "axis": [0, 0, 2], "radius": 2, "half_length": 1, "capped": false,
     "motion": {"pivot": [0, 0, 0], "axis": [0, 0, 1], "angular_velocity_degrees": 90, "velocity": [0, 0.5, 0]}},
    {"type": "plane", "point": [0, -3, 0], "normal": [0, 2, 0], "half_size": 4}
  ]
})";

TEST(SceneFile, CollisionKeysAreReadAndRoundTrip) {
  const SceneDesc scene = parse_scene(json::parse(collision_scene), "scene.json");
  EXPECT_EQ(scene.collision.repulsion_stiffness, 500.0);
  EXPECT_EQ(scene.collision.max_ccd_passes, 4);
  EXPECT_EQ(scene.collision.max_rounds, 2);
  EXPECT_EQ(scene.collision.strain_limit, 0.5);
  EXPECT_EQ(scene.collision.strain_limit_sweeps, 8);
  const ClothDesc& cloth = scene.cloths[0];
  EXPECT_EQ(cloth.thickness, 0.004);
  EXPECT_EQ(cloth.contact.static_friction, 0.6);
  EXPECT_EQ(cloth.contact.kinetic_friction, 0.5);
  EXPECT_FALSE(cloth.contact.self_collision);
  EXPECT_EQ(cloth.initial_velocity, Vec3(0, -2, 0));
  const Collider& capsule = scene.colliders[0];
  EXPECT_EQ(capsule.shape, ColliderShape::capsule);
  EXPECT_EQ(capsule.friction, 0.2);
  EXPECT_EQ(capsule.static_friction, 0.25);
  const Collider& drum = scene.colliders[1];
  EXPECT_EQ(drum.shape, ColliderShape::cylinder);
  EXPECT_FALSE(drum.capped);
  EXPECT_EQ(drum.axis, Vec3::UnitZ()) << "axes are normalised";
  EXPECT_NEAR(drum.motion.angular_velocity, pi / 2, 1e-15);
  EXPECT_EQ(drum.motion.velocity, Vec3(0, 0.5, 0));
  EXPECT_EQ(scene.colliders[2].static_friction, scene.colliders[2].friction) << "friction sets both by default";
  EXPECT_EQ(scene.colliders[2].normal, Vec3::UnitY());
  EXPECT_EQ(scene.colliders[2].plane_half_size, 4.0);

  const json written = scene_to_json(scene);
  EXPECT_EQ(scene_to_json(parse_scene(written, "scene.json")), written);
  const World world = build_world(scene);
  EXPECT_EQ(world.cloths()[0].state.v.col(5), Vec3(0, -2, 0));
}

TEST(SceneFile, CollisionKeyErrorsNameThePath) {
  expect_scene_error(collision_scene, {"colliders.0.type=\"cone\""}, "/colliders/0/type",
                     "expected one of \"plane\", \"sphere\", \"box\", \"capsule\", \"cylinder\", \"mesh\"");
  expect_scene_error(collision_scene, {"colliders.0.axis=[0,0,0]"}, "/colliders/0/axis", "non-zero vector");
  expect_scene_error(collision_scene, {"colliders.0.half_length=0"}, "/colliders/0/half_length", "> 0");
  expect_scene_error(collision_scene, {"colliders.0.capped=true"}, "/colliders/0/capped", "unknown key");
  expect_scene_error(collision_scene, {"colliders.1.motion.spin=1"}, "/colliders/1/motion/spin", "unknown key");
  expect_scene_error(collision_scene, {"colliders.1.motion.axis=[0,0,0]"}, "/colliders/1/motion/axis",
                     "non-zero vector");
  expect_scene_error(collision_scene, {"colliders.0.friction=-1"}, "/colliders/0/friction", ">= 0");
  expect_scene_error(collision_scene, {"cloths.0.friction.dynamic=1"}, "/cloths/0/friction/dynamic",
                     "unknown key");
  expect_scene_error(collision_scene, {"cloths.0.self_collision=1"}, "/cloths/0/self_collision",
                     "true or false");
  expect_scene_error(collision_scene, {"collision.max_rounds=0"}, "/collision/max_rounds",
                     "integer in [1, 100]");
  expect_scene_error(collision_scene, {"collision.strain_limit=-0.1"}, "/collision/strain_limit", ">= 0");
  expect_scene_error(collision_scene, {"collision.strain_limit_sweeps=0"}, "/collision/strain_limit_sweeps",
                     "integer in [1, 1000]");
  expect_scene_error(collision_scene, {"colliders.0={\"type\": \"mesh\"}"}, "/colliders/0",
                     "needs an OBJ file");
  expect_scene_error(collision_scene, {"colliders.0={\"type\": \"mesh\", \"obj\": \"nowhere.obj\"}"},
                     "/colliders/0/obj", "nowhere.obj");
}

TEST(SceneFile, MeshCollidersLoadTheirObjBesideTheScene) {
  testing::TempDir dir;
  std::ofstream(dir.file("ramp.obj")) << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n";
  std::ofstream(dir.file("scene.json")) << R"({"cloths": [{"grid": {"size": [1, 1], "resolution": [3, 3]}}],
                                              "colliders": [{"type": "mesh", "obj": "ramp.obj"}]})";
  const World world = build_world(load_scene_file(dir.file("scene.json")));
  ASSERT_EQ(world.colliders().size(), 1u);
  std::ofstream(dir.file("broken.obj")) << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 1 2\n";
  std::ofstream(dir.file("broken.json")) << R"({"colliders": [{"type": "mesh", "obj": "broken.obj"}]})";
  try {
    build_world(load_scene_file(dir.file("broken.json")));
    FAIL() << "a triangle repeating a vertex is an error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.json_path(), "/colliders/0/obj") << error.what();
  }
  EXPECT_EQ(world.collider_surface(0).num_triangles(), 1);
  EXPECT_EQ(world.collider_positions(0).col(1), Vec3(1, 0, 0));
}

TEST(SceneFile, TheBarrierResponseRefusesWhatItCannotHold) {
  expect_scene_error(minimal_scene,
                     {"solver.integrator=\"implicit_euler\"", "collision.response=\"barrier\"",
                      "colliders.0.motion.velocity=[0,1,0]"},
                     "/collision/response", "needs static colliders; collider 0");
  expect_scene_error(minimal_scene, {"collision.response=\"barrier\""}, "/collision/response",
                     "needs solver.integrator \"implicit_euler\"");
  expect_scene_error(minimal_scene, {"collision.response=\"soft\""}, "/collision/response", "impulse");
}

}  // namespace
}  // namespace weft
