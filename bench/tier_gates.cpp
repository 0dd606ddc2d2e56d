// The quality gates a fast tier must pass against the reference tier (issue 27; docs/performance.md,
// "Fast tier"), for a candidate given as scene overrides:
//   equilibrium  the drape's cloth (1 m, 16x16) hanging from two corners, 6 s damped at 2 /s,
//                within 0.5% of its size (largest vertex distance) of the converged reference
//                (Cholesky, residual 1e-8 m/s); with the collision phase on (self-collision, no
//                collider), so that a candidate's collision settings (a strain limit) act here
//                too (until 2026-11-26 it was off, and such a candidate was judged without them);
//   strain       the 32x32 drape's largest strain over 20 frames (through first contact and the
//                skirt's fall) within 10% of the reference tier's (the shipped settings);
//   clean        no intersecting triangle pair, no vertex inside the sphere, at any frame end
//                (tests/support/scene_invariants.hpp);
//   energy       no energy created over the drape: dissipated >= -1% of the initial energy,
//                and the budget closes (initial + external work - final - dissipated within 1%
//                of the initial energy), so that a phase cannot hide energy it made in a flow
//                (sim/energy_ledger.hpp).
// It prints one line per gate and exits 0 when all pass, 1 otherwise. A candidate that passes
// becomes a ctest (tests/sim) with its settings; until then the gates live here.
//   cmake --build build/release --target weft_tier_gates
//   build/release/bench/weft_tier_gates --set solver.newton.max_iterations=2
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"
#include "sim/world.hpp"
#include "support/scene_invariants.hpp"

namespace {

using namespace weft;

std::vector<std::string> with(std::vector<std::string> overrides, const std::vector<std::string>& more) {
  overrides.insert(overrides.end(), more.begin(), more.end());
  return overrides;
}

// The drape's cloth material, 1 m and 16x16, hanging from its two top corners, damped to settle.
SceneDesc hanging_cloth(const std::vector<std::string>& overrides) {
  auto document = nlohmann::json::parse(R"({
    "solver": {"integrator": "implicit_euler", "time_step": 0.004166666666666667},
    "fps": 30,
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [16, 16]},
      "transform": {"translation": [0, 1, 0], "rotation_degrees": [-60, 0, 0]},
      "density": 0.2, "mass_damping": 2,
      "membrane": {"young_modulus": 5e6, "poisson_ratio": 0.3, "thickness": 5e-4, "compression_factor": 0.01},
      "bending": {"stiffness": 2e-5},
      "pins": {"corners": ["top_left", "top_right"]}
    }]
  })");
  for (const std::string& assignment : overrides) apply_override(document, assignment, "<hanging cloth>");
  return parse_scene(document, "<hanging cloth>");
}

Positions settle(const SceneDesc& scene, double seconds) {
  World world = build_world(scene);
  const int steps = static_cast<int>(std::lround(seconds / world.settings.time_step));
  for (int s = 0; s < steps; ++s) world.step();
  return world.cloths()[0].state.x;
}

struct DrapeRun {
  double largest_strain = 0.0;
  int unclean_frames = 0;
  double initial_energy = 0.0;
  double final_energy = 0.0;
  EnergyFlows flows;
  double step_seconds = 0.0;
};

DrapeRun run_drape(const std::string& source_dir, const std::vector<std::string>& overrides) {
  const SceneDesc scene =
      load_scene_file(source_dir + "/scenes/drape_sphere.json", with({"cloths.0.grid.resolution=[32,32]"}, overrides));
  World world = build_world(scene);
  const testing::SceneInvariants invariants(world);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  DrapeRun run;
  run.initial_energy = world.energies().total();
  for (int frame = 0; frame < 20; ++frame) {
    for (int s = 0; s < schedule.steps_per_frame; ++s) {
      world.step();
      run.flows += world.last_step_stats().energy_flows;
      run.step_seconds += world.last_step_stats().total_ms / 1000.0;
    }
    run.largest_strain = std::max(run.largest_strain, largest_strain(world));
    run.unclean_frames += !invariants.check(world).ok();
  }
  run.final_energy = world.energies().total();
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> candidate;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--set") == 0 && k + 1 < argc) {
      candidate.push_back(argv[++k]);
    } else {
      std::fprintf(stderr, "usage: %s [--set path=value ...]  (the candidate tier's overrides)\n", argv[0]);
      return 2;
    }
  }
  try {
    const std::string source_dir = WEFT_SOURCE_DIR;
    bool all = true;
    const auto gate = [&](const char* name, bool pass, const std::string& detail) {
      std::printf("%-12s %s  %s\n", name, pass ? "pass" : "FAIL", detail.c_str());
      all = all && pass;
    };

    const Positions reference = settle(
        hanging_cloth({"solver.newton.tolerance=1e-8", "solver.newton.linear_solver=cholesky"}), 6.0);
    const Positions settled = settle(hanging_cloth(candidate), 6.0);
    const double distance = (settled - reference).colwise().norm().maxCoeff();
    gate("equilibrium", distance < 0.005, "largest distance " + std::to_string(1e3 * distance) + " mm (bound 5 mm)");

    const DrapeRun base = run_drape(source_dir, {});
    const DrapeRun fast = run_drape(source_dir, candidate);
    gate("strain", fast.largest_strain < 1.1 * base.largest_strain,
         "largest " + std::to_string(fast.largest_strain) + ", reference " + std::to_string(base.largest_strain) +
             " (bound +10%)");
    gate("clean", fast.unclean_frames == 0, std::to_string(fast.unclean_frames) + " frames with a violation");
    const double budget_error =
        fast.initial_energy + fast.flows.external_work - fast.final_energy - fast.flows.dissipated();
    gate("energy",
         fast.flows.dissipated() > -0.01 * fast.initial_energy &&
             std::abs(budget_error) <= 0.01 * fast.initial_energy,
         "dissipated " + std::to_string(fast.flows.dissipated()) + " J of " + std::to_string(fast.initial_energy) +
             " J initial, budget error " + std::to_string(budget_error) + " J (bound 1%)");
    std::printf("drape steps: %.2f s candidate, %.2f s reference (20 frames, 32x32, 1 thread; not a gate)\n",
                fast.step_seconds, base.step_seconds);
    return all ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "weft_tier_gates: %s\n", error.what());
    return 2;
  }
}
