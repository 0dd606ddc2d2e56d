// The energy budget (sim/energy_ledger.hpp): each flow against its closed form where one exists,
// the budget closing step by step, and every shipped scene (shortened) closing within 1% of its
// initial energy.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/implicit_euler.hpp"
#include "sim/energy_ledger.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

const std::string source_dir = WEFT_SOURCE_DIR;

struct BudgetRun {
  double initial = 0.0;         // J, kinetic + potential at the start
  EnergyFlows flows;            // summed over the run
  double largest_error = 0.0;   // J, largest |E + dissipated - initial - external work| after any step
  double final_energy = 0.0;
};

BudgetRun run_budget(World& world, int steps) {
  BudgetRun run;
  run.initial = world.energies().total();
  for (int s = 0; s < steps; ++s) {
    world.step();
    run.flows += world.last_step_stats().energy_flows;
    const double energy = world.energies().total();
    run.largest_error =
        std::max(run.largest_error, std::abs(energy + run.flows.dissipated() - run.initial - run.flows.external_work));
    run.final_energy = energy;
  }
  return run;
}

World world_from(const std::string& json) { return build_world(parse_scene(nlohmann::json::parse(json), "<inline>")); }

// A 1 m cloth, membrane only, falling freely (no collider, no damping).
World falling_cloth(const std::string& integrator) {
  return world_from(R"({"solver": {"integrator": ")" + integrator + R"(", "time_step": 0.01},
    "cloths": [{"grid": {"size": [1, 1], "resolution": [6, 6]}, "density": 0.2,
                "membrane": {"young_modulus": 1000, "poisson_ratio": 0.3}}]})");
}

TEST(EnergyBudget, FreeFallLosesHalfMGSquaredHSquaredAStepToEitherEuler) {
  // Both Euler updates give v1 = v0 - g h, x1 = x0 + h v1 in free fall, whose energy falls by
  // exactly 1/2 M g^2 h^2 a step (M the total mass): the integrator's loss, nothing else.
  for (const std::string integrator : {"implicit_euler", "symplectic_euler"}) {
    World world = falling_cloth(integrator);
    const double mass = world.cloths()[0].model.mass.sum();
    const int steps = 50;
    const BudgetRun run = run_budget(world, steps);
    const double g = 9.81, h = world.settings.time_step;  // 1/120 s: a 1/60 s frame in two
    EXPECT_NEAR(run.flows.integrator, steps * 0.5 * mass * g * g * h * h, 1e-9) << integrator;
    EXPECT_NEAR(run.initial - run.final_energy, run.flows.integrator, 1e-9) << integrator;
    EXPECT_NEAR(run.flows.damping, 0.0, 1e-12) << integrator;
    EXPECT_EQ(run.flows.external_work, 0.0) << integrator;
    EXPECT_EQ(run.flows.contact, 0.0) << integrator;
  }
}

// A damped 12x12 spring cloth hanging from two corners (as test_hanging_cloth), 1 s.
World hanging_cloth(const std::string& solver) {
  return world_from(R"({"solver": )" + solver + R"(, "fps": 50,
    "cloths": [{"grid": {"size": [1, 1], "resolution": [12, 12]},
      "transform": {"translation": [0, 1, 0], "rotation_degrees": [-90, 0, 0]},
      "density": 0.2, "mass_damping": 0.5,
      "springs": {"structural": {"stiffness": 300, "damping": 0.1}, "shear": {"stiffness": 60, "damping": 0.05},
                  "bend": {"stiffness": 5, "damping": 0.01}},
      "pins": {"corners": ["top_left", "top_right"]}}]})");
}

TEST(EnergyBudget, SymplecticEulerBudgetClosesOnADampedHangingCloth) {
  World world = hanging_cloth(R"({"integrator": "symplectic_euler", "time_step": 0.0005})");
  const BudgetRun run = run_budget(world, 2000);
  const double fallen = run.initial - run.final_energy;
  EXPECT_GT(fallen, 0.05) << "the cloth swung down and settled";
  // The identity is exact: only round-off is left.
  EXPECT_LT(run.largest_error, 1e-9 * std::abs(run.initial) + 1e-9);
  EXPECT_GT(run.flows.damping, 0.5 * fallen) << "damping took most of the fall's energy";
  EXPECT_EQ(run.flows.external_work, 0.0) << "the pins held still";
}

TEST(EnergyBudget, ImplicitEulerBudgetClosesToTheNewtonResidual) {
  World world = hanging_cloth(
      R"({"integrator": "implicit_euler", "time_step": 0.005, "newton": {"tolerance": 1e-9, "linear_solver": "cholesky"}})");
  const BudgetRun run = run_budget(world, 200);
  EXPECT_GT(run.initial - run.final_energy, 0.05);
  EXPECT_LT(run.largest_error, 1e-6 * std::abs(run.initial) + 1e-7);
  EXPECT_GT(run.flows.damping, 0.0);
  EXPECT_GT(run.flows.integrator, 0.0) << "implicit Euler dissipates";
  EXPECT_EQ(run.flows.external_work, 0.0);
}

TEST(EnergyBudget, ACappedNewtonSolveBooksItsResidualsWork) {
  // One Newton iteration a step leaves each step unconverged. The work of the force it left
  // unbalanced is booked as the residual flow, so the budget closes as tightly as a converged
  // run's, and the flow shows what the converged run's does not (unbooked, it would show only in
  // the budget's error).
  World tight = hanging_cloth(R"({"integrator": "implicit_euler", "time_step": 0.02, "newton": {"tolerance": 1e-9}})");
  World capped = hanging_cloth(
      R"({"integrator": "implicit_euler", "time_step": 0.02, "newton": {"tolerance": 1e-3, "max_iterations": 1}})");
  const BudgetRun tight_run = run_budget(tight, 50);
  const BudgetRun capped_run = run_budget(capped, 50);
  const double scale = std::abs(capped_run.initial);
  EXPECT_GT(std::abs(capped_run.flows.residual), 1e-3 * scale) << "the capped steps left work unbooked by the identity";
  EXPECT_GT(std::abs(capped_run.flows.residual), 1e4 * std::abs(tight_run.flows.residual));
  EXPECT_LT(capped_run.largest_error, 1e-9 * scale + 1e-9);
  EXPECT_LT(tight_run.largest_error, 1e-6 * scale + 1e-7);
}

TEST(EnergyBudget, TheSolversLastEvaluationBooksWhatAFreshOneWould) {
  // The ledger takes U, the penalty and the incremental potential's gradient at the step's end
  // from the solver's last evaluation when it was taken at the cloth's positions
  // (ImplicitEulerSolver::last_evaluation_at). One capped Newton iteration (residual left) with the
  // pinned corners rising (external work): every flow as an evaluation of its own gives it.
  World world = hanging_cloth(
      R"({"integrator": "implicit_euler", "time_step": 0.02, "newton": {"tolerance": 1e-9, "max_iterations": 1}})");
  run_budget(world, 5);
  Cloth cloth = world.cloths()[0];
  for (Eigen::Index i = 0; i < cloth.state.v.cols(); ++i) {
    if (cloth.model.inverse_mass[i] == 0.0) cloth.state.v.col(i) = Vec3(0.0, 0.5, 0.0);
  }
  const Vec3 gravity = world.settings.gravity;
  const double h = world.settings.time_step;
  SolveLedger ledger;
  ledger.begin(cloth, gravity, false);
  ImplicitEulerSolver solver;
  solver.step(cloth, gravity, h, world.settings.implicit);
  const IncrementalPotentialParts* parts = solver.last_evaluation_at(cloth.state.x);
  ASSERT_NE(parts, nullptr) << "the step's last evaluation was at its end";
  const EnergyFlows reused = ledger.implicit_euler(cloth, gravity, h, nullptr, parts);
  const EnergyFlows fresh = ledger.implicit_euler(cloth, gravity, h, nullptr, nullptr);
  EXPECT_GT(reused.external_work, 1e-4) << "the rising pins did work";
  EXPECT_GT(std::abs(reused.residual), 1e-6) << "one iteration left a residual";
  const double tolerance = 1e-12 * (std::abs(fresh.integrator) + std::abs(fresh.external_work) + 1.0);
  EXPECT_NEAR(reused.external_work, fresh.external_work, tolerance);
  EXPECT_NEAR(reused.damping, fresh.damping, tolerance);
  EXPECT_NEAR(reused.integrator, fresh.integrator, tolerance);
  EXPECT_NEAR(reused.residual, fresh.residual, tolerance);
  EXPECT_NEAR(reused.contact, fresh.contact, tolerance);
  Positions moved = cloth.state.x;
  moved(1, 0) = std::nextafter(moved(1, 0), 2.0);
  EXPECT_EQ(solver.last_evaluation_at(moved), nullptr) << "a point one ulp away is another point";
}

TEST(EnergyBudget, AnEditBetweenStepsIsMeasuredOnTheEditedCloth) {
  // The collision phase's end measures U for the contact flow and the next step starts from it
  // (SolveLedger::carry_potential) instead of evaluating U again. A live edit in between (the
  // viewer's stiffness slider) changes U at the same positions: the step after it must measure
  // the edited cloth, and its budget close from the energy the edit left.
  World world = hanging_cloth(
      R"({"integrator": "implicit_euler", "time_step": 0.005, "newton": {"tolerance": 1e-9, "linear_solver": "cholesky"}})");
  ASSERT_TRUE(world.settings.collision.enabled) << "the carried potential is the collision phase's";
  run_budget(world, 20);
  const double before_edit = world.energies().total();
  world.cloths()[0].model.springs.stiffness *= 2.0;
  const BudgetRun run = run_budget(world, 20);
  EXPECT_GT(std::abs(run.initial - before_edit), 1e-4) << "the edit changed the stretched springs' energy";
  EXPECT_LT(run.largest_error, 1e-6 * std::abs(run.initial) + 1e-7);
}

TEST(EnergyBudget, AMovingPinsWorkIsExternalAndTheBudgetCloses) {
  // A 1 m membrane cloth hung from a pin that rises at 0.5 m/s: the pin lifts the cloth.
  for (const std::string integrator : {"implicit_euler", "symplectic_euler"}) {
    const std::string h = integrator == "implicit_euler" ? "0.004" : "0.0002";
    World world = world_from(R"({"solver": {"integrator": ")" + integrator + R"(", "time_step": )" + h +
                             R"(, "newton": {"tolerance": 1e-9}}, "fps": 50,
      "cloths": [{"grid": {"size": [1, 1], "resolution": [8, 8]},
        "transform": {"translation": [0, 1, 0], "rotation_degrees": [-90, 0, 0]}, "density": 0.2,
        "mass_damping": 0.2, "membrane": {"young_modulus": 2000, "poisson_ratio": 0.3},
        "moving_pins": [{"corners": ["top_left", "top_right"], "velocity": [0, 0.5, 0]}]}]})");
    const int steps = integrator == "implicit_euler" ? 250 : 5000;
    const BudgetRun run = run_budget(world, steps);
    EXPECT_GT(run.flows.external_work, 0.1 * std::abs(run.initial)) << integrator;
    EXPECT_LT(run.largest_error, 1e-5 * std::abs(run.flows.external_work)) << integrator;
  }
}

TEST(EnergyBudget, TheDrapeClosesThroughItsHardestContactSteps) {
  // At the 32x32 drape's frame 18 a hinge wing collapses while Phi still falls, and a solve that
  // ended on its last iterate would leave residuals of ~1e5 m/s and break the budget: the solve
  // returns its best iterate. The residual's work is booked (the residual flow); the budget error
  // is what no flow books.
  const SceneDesc scene = load_scene_file(source_dir + "/scenes/drape_sphere.json", {"cloths.0.grid.resolution=[32,32]"});
  World world = build_world(scene);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  BudgetRun run;
  run.initial = world.energies().total();
  double largest_residual = 0.0;
  for (int s = 0; s < 20 * schedule.steps_per_frame; ++s) {
    world.step();
    run.flows += world.last_step_stats().energy_flows;
    largest_residual = std::max(largest_residual, world.last_step_stats().residual);
    const double energy = world.energies().total();
    run.largest_error =
        std::max(run.largest_error, std::abs(energy + run.flows.dissipated() - run.initial - run.flows.external_work));
  }
  EXPECT_LT(run.largest_error, 0.01 * run.initial);
  EXPECT_LT(largest_residual, 100.0) << "m/s";
}

// The twist winds its cloth into a rope from frame ~24 on; from there its Newton solves need up to
// ~170 iterations (32x16; the median step 13). With the default cap of 30 most of them would end
// unconverged, so the scene sets max_iterations 200. In the rope, wings collapse to slivers and
// the dihedral bending's forces (1/height) stall the solves, so that the budget's error passes 1%
// before frame 90; the scene uses the quadratic model, whose forces stay bounded. Run through the
// rope at a quarter of its vertices with the shipped solver settings.
TEST(EnergyBudget, TheTwistClosesThroughItsRope) {
  const SceneDesc scene = load_scene_file(source_dir + "/scenes/twist.json", {"cloths.0.grid.resolution=[32,16]"});
  World world = build_world(scene);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  const BudgetRun run = run_budget(world, 90 * schedule.steps_per_frame);
  EXPECT_LT(run.largest_error, 0.01 * run.initial)
      << "external work " << run.flows.external_work << " J, integrator " << run.flows.integrator << " J, contact "
      << run.flows.contact << " J";
}

// Every shipped scene, shortened: the budget closes within 1% of the initial energy after every
// step (docs/recording.md, "Energy budget", lists them at full length).
TEST(EnergyBudget, EveryShippedSceneClosesWithinOnePercent) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> scenes = {
      {"default", {}},
      {"drape_sphere", {"cloths.0.grid.resolution=[16,16]", "cloths.0.transform.translation=[0,0.65,0]"}},
      {"drape_sphere_fast", {"cloths.0.grid.resolution=[16,16]", "cloths.0.transform.translation=[0,0.65,0]"}},
      {"drape_five_sheets",
       {"cloths.0.grid.resolution=[12,12]", "cloths.1.grid.resolution=[12,12]", "cloths.2.grid.resolution=[12,12]",
        "cloths.3.grid.resolution=[12,12]", "cloths.4.grid.resolution=[12,12]"}},
      {"fast_drop", {"cloths.0.grid.resolution=[16,16]"}},
      {"friction_slope", {"cloths.0.grid.resolution=[10,10]"}},
      {"soft_balls", {}},
      {"swing", {}},
      {"tumble_dryer",
       {"cloths.0.grid.resolution=[8,8]", "cloths.1.grid.resolution=[8,8]", "cloths.2.grid.resolution=[8,8]",
        "cloths.3.grid.resolution=[8,8]"}},
      {"twist", {"cloths.0.grid.resolution=[16,8]"}},
      {"twist_five_turns", {"cloths.0.grid.resolution=[16,8]"}},
      {"two_sheets", {"cloths.0.grid.resolution=[14,14]", "cloths.1.grid.resolution=[12,12]"}},
  };
  int checked = 0;
  for (const auto& [name, overrides] : scenes) {
    const SceneDesc scene = load_scene_file(source_dir + "/scenes/" + name + ".json", overrides);
    World world = build_world(scene);
    const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
    const BudgetRun run = run_budget(world, 12 * schedule.steps_per_frame);
    const std::string budget = name + ": initial " + std::to_string(run.initial) + " J, external work " +
                               std::to_string(run.flows.external_work) + " J, dissipated: damping " +
                               std::to_string(run.flows.damping) + ", integrator " +
                               std::to_string(run.flows.integrator) + ", contact " +
                               std::to_string(run.flows.contact) + ", plastic " + std::to_string(run.flows.plastic) +
                               ", residual " + std::to_string(run.flows.residual);
    EXPECT_LT(run.largest_error, 0.01 * std::abs(run.initial)) << budget;
    // Energy is never created overall where nothing moves the cloth but the pins (the drum of
    // the tumble dryer does work through contact, booked in the contact term). The contact
    // phase alone adds energy at a step (the proximity response's push-out leaves an outward
    // velocity; implicit Euler removes it the next step: docs/recording.md). Known exception:
    // soft_balls and drape_five_sheets, where the collision phase adds a few percent of the
    // initial energy more than the integrator removes over these 12 frames (the stacked sheets at
    // 32 x 32 over their whole second: the contact phase adds 1,739 J, implicit Euler removes
    // 1,740 J, from 21 J at the start), so the check leaves them out.
    if (name != "tumble_dryer" && name != "soft_balls" && name != "drape_five_sheets") {
      EXPECT_GT(run.flows.dissipated(), -0.01 * std::abs(run.initial)) << budget;
    }
    ++checked;
  }
  // Every scene file is in the list above.
  int shipped = 0;
  for (const auto& entry : std::filesystem::directory_iterator(source_dir + "/scenes")) {
    shipped += entry.path().extension() == ".json";
  }
  EXPECT_EQ(checked, shipped);
}

}  // namespace
}  // namespace weft
