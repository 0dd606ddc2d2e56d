// A cloth pinned at two corners swings down and comes to rest; the pins never move; the
// pipeline's bookkeeping (time, frame schedule, energies) is consistent.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

World hanging_cloth_world() {
  const auto document = nlohmann::json::parse(R"({
    "solver": {"time_step": 0.0005},
    "fps": 50,
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [12, 12]},
      "transform": {"translation": [0, 1, 0], "rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "mass_damping": 0.5,
      "springs": {"structural": {"stiffness": 300, "damping": 0.1},
                  "shear": {"stiffness": 60, "damping": 0.05},
                  "bend": {"stiffness": 5, "damping": 0.01}},
      "pins": {"corners": ["top_left", "top_right"]}
    }]
  })");
  return build_world(parse_scene(document, "<inline>"));
}

TEST(HangingCloth, SwingsDownAndComesToRestWithPinsFixed) {
  World world = hanging_cloth_world();
  const Cloth& cloth = world.cloths()[0];
  const int top_left = 11 * 12, top_right = 11 * 12 + 11;
  const Vec3 pin_left = cloth.state.x.col(top_left);
  const Vec3 pin_right = cloth.state.x.col(top_right);
  const double initial_potential = world.energies().gravitational;

  double peak_kinetic = 0.0;
  while (world.time() < 40.0) {
    world.step();
    peak_kinetic = std::max(peak_kinetic, world.energies().kinetic);
  }
  const Energies final_energies = world.energies();
  // It fell (lost potential energy) and its motion was real, then died out.
  EXPECT_LT(final_energies.gravitational, initial_potential - 0.05);
  EXPECT_GT(peak_kinetic, 0.02);
  EXPECT_LT(final_energies.kinetic, 1e-6 * peak_kinetic);
  // Pins are exactly where they started.
  EXPECT_EQ(cloth.state.x.col(top_left), pin_left);
  EXPECT_EQ(cloth.state.x.col(top_right), pin_right);
  // At rest the cloth hangs below its pins, with its lowest point roughly a cloth length down.
  const double lowest = cloth.state.x.row(1).minCoeff();
  EXPECT_LT(lowest, 1.0 - 0.9);
  EXPECT_GT(lowest, 1.0 - 1.6);
  EXPECT_TRUE(cloth.state.x.allFinite());
}

TEST(HangingCloth, FrameScheduleCutsFramesIntoEqualSteps) {
  EXPECT_EQ(frame_schedule(60.0, 1.0 / 600.0).steps_per_frame, 10);
  const FrameSchedule odd = frame_schedule(30.0, 0.001);
  EXPECT_EQ(odd.steps_per_frame, 34);
  EXPECT_LE(odd.time_step, 0.001);
  EXPECT_NEAR(odd.time_step * odd.steps_per_frame, 1.0 / 30.0, 1e-15);
  EXPECT_EQ(frame_schedule(24.0, 1.0).steps_per_frame, 1);
}

TEST(HangingCloth, FrameScheduleRefusesStepCountsPastTheBound) {
  // 3.3e10 steps would overflow the int and come out as one step of 1/30 s.
  EXPECT_THROW(frame_schedule(30.0, 1e-12), std::out_of_range);
  EXPECT_DOUBLE_EQ(steps_per_frame(30.0, 1e-12), std::ceil(1.0 / 30.0 / 1e-12 - 1e-9));
  EXPECT_EQ(frame_schedule(1.0, 1.0 / max_steps_per_frame).steps_per_frame, max_steps_per_frame);
  EXPECT_THROW(frame_schedule(1.0, 0.99 / max_steps_per_frame), std::out_of_range);
}

TEST(HangingCloth, SubstepsAdvanceTimeByOneTimeStep) {
  World world = hanging_cloth_world();
  world.settings.substeps = 4;
  world.step();
  EXPECT_NEAR(world.time(), world.settings.time_step, 1e-15);
}

}  // namespace
}  // namespace weft
