#include "physics/adaptive_stepping.hpp"

#include <algorithm>
#include <cmath>

#include "physics/midpoint_euler_cromer.hpp"
#include "physics/symplectic_euler.hpp"

namespace weft {

namespace {

int order_of(IntegratorKind kind) { return kind == IntegratorKind::symplectic_euler ? 1 : 2; }

void explicit_step(IntegratorKind kind, Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace) {
  switch (kind) {
    case IntegratorKind::symplectic_euler:
      symplectic_euler_step(cloth.model, cloth.state, gravity, h);
      return;
    case IntegratorKind::midpoint_euler_cromer:
      midpoint_euler_cromer_step(cloth, gravity, h, workspace);
      return;
    default:
      explicit_midpoint_step(cloth, gravity, h, workspace);
      return;
  }
}

}  // namespace

void adaptive_advance(Cloth& cloth, IntegratorKind kind, const Vec3& gravity, double duration,
                      const AdaptiveSettings& settings, AdaptiveState& state, ExplicitWorkspace& workspace,
                      ClothState& trial) {
  if (state.next_step <= 0.0) state.next_step = std::clamp(duration, settings.h_min, settings.h_max);
  workspace.resize(cloth.num_vertices());
  const int order = order_of(kind);
  const double richardson = std::pow(2.0, order) - 1.0;
  double remaining = duration;
  while (remaining > 1e-15 * duration) {
    const double h = std::min(state.next_step, remaining);
    // The whole step into `trial`, then the two halves from the same start in cloth.state.
    workspace.x_start = cloth.state.x;
    workspace.v_start = cloth.state.v;
    explicit_step(kind, cloth, gravity, h, workspace);
    trial.x = cloth.state.x;
    trial.v = cloth.state.v;
    cloth.state.x = workspace.x_start;
    cloth.state.v = workspace.v_start;
    explicit_step(kind, cloth, gravity, 0.5 * h, workspace);
    explicit_step(kind, cloth, gravity, 0.5 * h, workspace);
    const double error = (cloth.state.x - trial.x).lpNorm<Eigen::Infinity>() / richardson;

    const bool finite = std::isfinite(error);
    const double factor =
        !finite ? 0.2 : error > 0.0 ? std::clamp(0.9 * std::pow(settings.tolerance / error, 1.0 / (order + 1)), 0.2, 2.0)
                                    : 2.0;
    const bool at_minimum = h <= settings.h_min * (1.0 + 1e-12);
    if (finite && error <= settings.tolerance) {
      ++state.accepted;
      state.last_error = error;
      remaining -= h;
    } else if (at_minimum) {
      // The tolerance cannot be met at the smallest step allowed: taken, and counted.
      ++state.accepted;
      ++state.unmet;
      state.last_error = error;
      remaining -= h;
    } else {
      // Rejected: back to the start of the step, retried smaller.
      cloth.state.x = workspace.x_start;
      cloth.state.v = workspace.v_start;
      ++state.rejected;
    }
    state.next_step = std::clamp(h * factor, settings.h_min, settings.h_max);
  }
}

}  // namespace weft
