#pragma once
// The quality gates a fast tier must pass against the reference tier (docs/performance.md,
// "The fast tier"), so that settings that make the drape faster cannot make it wrong. The
// candidate is the drape scene as shipped (scenes/drape_sphere.json: collision.strain_limit 0.02,
// membrane.min_stretch 0.5) plus overrides; the reference tier is the same Newton + CCD pipeline
// without a tight strain limit (`reference_tier`: the limit at 1.0; the membrane as shipped, with
// its min_stretch). The drape runs as shipped: 64x64, 30 frames (the peers' scene; settings that
// lock the drape into an umbrella at 64x64 can leave it free at 32x32).
//   equilibrium  the drape's cloth (1 m, 16x16) hanging from two corners, with the candidate's
//                solver and collision settings (its Newton solves converged to 1e-5 m/s, see
//                `converged_hanging`), 6 s damped at 2 /s, within 0.5% of its size (largest
//                vertex distance) of the converged reference (the reference tier, Cholesky,
//                residual 1e-8 m/s); with the collision phase on (self-collision, no collider),
//                so that a candidate's collision settings (a strain limit) act here too;
//   strain       the drape's largest strain over its frames at most 10% above the reference
//                tier's (a tier that stretches less passes: the gate catches under-converged
//                stiffness);
//   shape        the drape's mean height at its last frame within 5 cm (2.5% of the cloth's size)
//                of the reference tier's: a tier that locks (a skirt held out stiffly) fails;
//   clean        no intersecting triangle pair, no vertex inside the sphere, no edge over the
//                strain limit, at any frame end (scene_invariants.hpp);
//   energy       no energy created over the drape: dissipated >= -1% of the initial energy, and
//                the budget closes (initial + external work - final - dissipated within 1% of
//                the initial energy), so that a phase cannot hide energy it made in a flow
//                (sim/energy_ledger.hpp).
// Used by bench/tier_gates.cpp (prints them for a candidate) and tests/sim/test_tier_gates.cpp
// (the shipped settings and the fast tier pass them; h = 1/120 s with a 1% limit and without the
// collider contacts in the solve does not, nor would a capped solve whose residual's work went
// unbooked).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"
#include "sim/world.hpp"
#include "support/files.hpp"
#include "support/scene_invariants.hpp"

namespace weft::testing {

// The equilibrium gate judges the formulation (step, strain limit, stiffness) with its solves
// converged: the drape's Newton tolerance of 1e-2 m/s stops a slowly settling cloth short of its
// rest (reference and fast tier alike), which is reported beside the gate, not gated. A
// candidate that sets solver.newton.tolerance itself is judged at its own.
inline const std::string converged_hanging = "solver.newton.tolerance=1e-5";

// The reference tier, as overrides of the drape scene: h = 1/240 s and no tight strain limit.
inline const std::vector<std::string> reference_tier = {"solver.time_step=0.004166666666666667",
                                                        "collision.strain_limit=1.0"};

// Weft's fast tier, as overrides of the drape scene (scenes/drape_sphere_fast.json is the drape
// with these; docs/performance.md, "The fast tier"): h = 1/90 s (three steps a frame), two Newton
// iterations a step (each step's residual still reported, its work booked by the energy ledger as
// the residual flow), a 5% strain limit (at 2% the capped solves' stretched impact steps set
// off impact zones large enough to stop the skirt's swing early), and steps cut into sub-steps
// where a vertex would travel more than 4 edge lengths (at 256x256 the skirt travels 9-12 edges a
// step, and the impact zones that motion grows tear the cloth).
inline const std::vector<std::string> fast_tier = {
    "solver.time_step=0.011111111111111112", "solver.newton.max_iterations=2", "collision.strain_limit=0.05",
    "solver.max_travel_edges=4"};

// The shape gate's bound on the difference of the drapes' final mean heights (m).
constexpr double shape_tolerance = 0.05;

inline std::vector<std::string> with(std::vector<std::string> overrides,
                                     const std::vector<std::string>& more) {
  overrides.insert(overrides.end(), more.begin(), more.end());
  return overrides;
}

// The drape's cloth material, 1 m and 16x16, hanging from its two top corners, damped to settle,
// under the drape scene's solver and collision settings (then the overrides).
inline SceneDesc hanging_cloth(const std::string& source_dir, const std::vector<std::string>& overrides) {
  const std::string drape_path = source_dir + "/scenes/drape_sphere.json";
  const nlohmann::json drape = read_json(drape_path);
  if (drape.is_discarded()) throw std::runtime_error("cannot read " + drape_path + " as JSON");
  auto document = nlohmann::json::parse(R"({
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
  document["solver"] = drape.at("solver");
  if (drape.contains("collision")) document["collision"] = drape.at("collision");
  for (const std::string& assignment : overrides) apply_override(document, assignment);
  return parse_scene(document, "<hanging cloth>");
}

inline Positions settle(const SceneDesc& scene, double seconds) {
  World world = build_world(scene);
  const int steps = static_cast<int>(std::lround(seconds / world.settings.time_step));
  for (int s = 0; s < steps; ++s) world.step();
  return world.cloths()[0].state.x;
}

struct DrapeRun {
  double largest_strain = 0.0;
  double final_mean_height = 0.0;  // m, the cloth's mean vertex height at the last frame
  double final_lowest = 0.0;       // m, its lowest vertex there
  int unclean_frames = 0;
  double initial_energy = 0.0;
  double final_energy = 0.0;
  EnergyFlows flows;
  double step_seconds = 0.0;

  // initial + external work - final - dissipated: what no flow accounts for.
  double budget_error() const {
    return initial_energy + flows.external_work - final_energy - flows.dissipated();
  }
  // The energy gate: nothing created (dissipated >= -1% of the initial energy), the budget closed to 1%.
  bool energy_closes() const {
    return flows.dissipated() > -0.01 * initial_energy && std::abs(budget_error()) <= 0.01 * initial_energy;
  }
};

// The drape as shipped (64x64, its 30 frames) under the overrides.
inline DrapeRun run_drape(const std::string& source_dir, const std::vector<std::string>& overrides) {
  const SceneDesc scene = load_scene_file(source_dir + "/scenes/drape_sphere.json", overrides);
  World world = build_world(scene);
  const SceneInvariants invariants(world);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  DrapeRun run;
  run.initial_energy = world.energies().total();
  for (int frame = 0; frame < scene.frames; ++frame) {
    for (int s = 0; s < schedule.steps_per_frame; ++s) {
      world.step();
      run.flows += world.last_step_stats().energy_flows;
      run.step_seconds += world.last_step_stats().total_ms / 1000.0;
    }
    run.largest_strain = std::max(run.largest_strain, largest_strain(world));
    run.unclean_frames += !invariants.check(world).ok();
  }
  run.final_energy = world.energies().total();
  const Positions& x = world.cloths()[0].state.x;
  run.final_mean_height = x.row(1).mean();
  run.final_lowest = x.row(1).minCoeff();
  return run;
}

struct TierGates {
  double equilibrium_distance = 0.0;  // m, the candidate's hanging cloth from the reference's
  double loose_distance = 0.0;        // m, the same at the scene's own Newton tolerance (not a gate)
  DrapeRun reference;
  DrapeRun candidate;

  bool equilibrium() const { return equilibrium_distance < 0.005; }
  bool strain() const { return candidate.largest_strain < 1.1 * reference.largest_strain; }
  bool shape() const {
    return std::abs(candidate.final_mean_height - reference.final_mean_height) <= shape_tolerance;
  }
  bool clean() const { return candidate.unclean_frames == 0; }
  bool energy() const { return candidate.energy_closes(); }
  bool all() const { return equilibrium() && strain() && shape() && clean() && energy(); }
};

inline TierGates judge_tier(const std::string& source_dir, const std::vector<std::string>& candidate) {
  TierGates gates;
  const Positions reference =
      settle(hanging_cloth(source_dir, with(reference_tier, {"solver.newton.tolerance=1e-8",
                                                             "solver.newton.linear_solver=cholesky"})),
             6.0);
  const Positions settled = settle(hanging_cloth(source_dir, with({converged_hanging}, candidate)), 6.0);
  gates.equilibrium_distance = (settled - reference).colwise().norm().maxCoeff();
  const Positions loose = settle(hanging_cloth(source_dir, candidate), 6.0);
  gates.loose_distance = (loose - reference).colwise().norm().maxCoeff();
  gates.reference = run_drape(source_dir, reference_tier);
  gates.candidate = run_drape(source_dir, candidate);
  return gates;
}

}  // namespace weft::testing
