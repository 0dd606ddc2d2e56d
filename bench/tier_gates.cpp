// The quality gates a fast tier must pass against the reference tier, printed for a candidate
// given as overrides of the drape scene as shipped (the gates: tests/support/tier_gates.hpp;
// docs/performance.md, "The fast tier"). One line per gate; exit 0 when
// all pass, 1 otherwise. The shipped settings are a ctest (tests/sim/test_tier_gates.cpp).
//   cmake --build build/release --target weft_tier_gates
//   build/release/bench/weft_tier_gates                      (the shipped drape settings)
//   build/release/bench/weft_tier_gates --set solver.newton.max_iterations=2
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "support/tier_gates.hpp"

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
    const weft::testing::TierGates gates = weft::testing::judge_tier(WEFT_SOURCE_DIR, candidate);
    const auto line = [](const char* name, bool pass, const std::string& detail) {
      std::printf("%-12s %s  %s\n", name, pass ? "pass" : "FAIL", detail.c_str());
    };
    line("equilibrium", gates.equilibrium(),
         "largest distance " + std::to_string(1e3 * gates.equilibrium_distance) + " mm (bound 5 mm)");
    std::printf("             at the scene's own Newton tolerance: %.3f mm (not a gate)\n",
                1e3 * gates.loose_distance);
    line("strain", gates.strain(),
         "largest " + std::to_string(gates.candidate.largest_strain) + ", reference " +
             std::to_string(gates.reference.largest_strain) + " (bound +10%)");
    char shape[160];
    std::snprintf(shape, sizeof shape,
                  "mean height %.3f m, reference %.3f m (bound 5 cm); lowest %.3f / %.3f m",
                  gates.candidate.final_mean_height, gates.reference.final_mean_height,
                  gates.candidate.final_lowest, gates.reference.final_lowest);
    line("shape", gates.shape(), shape);
    line("clean", gates.clean(), std::to_string(gates.candidate.unclean_frames) + " frames with a violation");
    line("energy", gates.energy(),
         "dissipated " + std::to_string(gates.candidate.flows.dissipated()) + " J (of which the Newton residual's " +
             std::to_string(gates.candidate.flows.residual) + ") of " +
             std::to_string(gates.candidate.initial_energy) + " J initial, budget error " +
             std::to_string(gates.candidate.budget_error()) + " J (bound 1%)");
    std::printf("drape steps: %.2f s candidate, %.2f s reference (1 thread; not a gate)\n",
                gates.candidate.step_seconds, gates.reference.step_seconds);
    return gates.all() ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "weft_tier_gates: %s\n", error.what());
    return 2;
  }
}
