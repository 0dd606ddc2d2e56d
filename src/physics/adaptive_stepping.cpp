#include "physics/adaptive_stepping.hpp"

#include <algorithm>
#include <cmath>

#include "physics/symplectic_euler.hpp"

namespace weft {

void adaptive_advance(Cloth& cloth, IntegratorKind kind, const Vec3& gravity, double duration,
                      const AdaptiveSettings& settings, AdaptiveState& state, ExplicitWorkspace& workspace,
                      ClothState& trial) {
  if (state.next_step <= 0.0) state.next_step = std::clamp(duration, settings.h_min, settings.h_max);
  if (trial.force.cols() != cloth.num_vertices()) trial.force.setZero(3, cloth.num_vertices());
  double remaining = duration;
  while (remaining > 1e-15 * duration) {
    const double h = std::min(state.next_step, remaining);
    // Both solutions: `trial` takes the symplectic Euler step, cloth.state the midpoint step.
    trial.x = cloth.state.x;
    trial.v = cloth.state.v;
    symplectic_euler_step(cloth.model, trial, gravity, h);
    workspace.resize(cloth.num_vertices());
    workspace.x_start = cloth.state.x;
    workspace.v_start = cloth.state.v;
    midpoint_step(cloth, gravity, h, workspace);
    const double error = (cloth.state.x - trial.x).lpNorm<Eigen::Infinity>();
    const double factor = error > 0.0 ? std::clamp(0.9 * std::sqrt(settings.tolerance / error), 0.2, 2.0) : 2.0;
    const bool at_minimum = h <= settings.h_min * (1.0 + 1e-12);
    if (error <= settings.tolerance || at_minimum || !std::isfinite(error)) {
      if (kind == IntegratorKind::symplectic_euler) {
        cloth.state.x = trial.x;
        cloth.state.v = trial.v;
      }
      ++state.accepted;
      state.last_error = error;
      remaining -= h;
    } else {
      // Rejected: restore the start of the step and retry smaller.
      cloth.state.x = workspace.x_start;
      cloth.state.v = workspace.v_start;
      ++state.rejected;
    }
    state.next_step = std::clamp(h * factor, settings.h_min, settings.h_max);
    if (!std::isfinite(error)) break;
  }
}

}  // namespace weft
