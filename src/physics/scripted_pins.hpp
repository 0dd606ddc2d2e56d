#pragma once
// Scripted (moving) pins: pinned vertices that follow a rigid motion in time,
//   x(t) = center + velocity t + R(axis, angular_velocity t) (x(0) - center),
// i.e. a rotation about an axis through `center` while the whole group translates. They have
// infinite mass (inverse_mass 0): the integrators never move them; the World sets their
// velocity so that the step carries them exactly to their target, then places them there.
#include <vector>

#include "core/math.hpp"

namespace weft {

struct PinScript {
  std::vector<int> vertices;       // pinned vertex indices
  Positions start_positions;       // their positions at t = 0 (3 x n_pinned)
  Vec3 velocity = Vec3::Zero();    // m/s
  Vec3 center = Vec3::Zero();      // m, a point on the rotation axis at t = 0
  Vec3 axis = Vec3::UnitY();       // unit rotation axis
  double angular_velocity = 0.0;   // rad/s, right-handed about `axis`
};

// Where pinned vertex k of `script` is at time t.
Vec3 scripted_pin_position(const PinScript& script, int k, double t);

// Before a step from t to t + h: gives each scripted vertex the velocity that carries it to
// its position at t + h.
void drive_scripted_pins(const std::vector<PinScript>& scripts, double t, double h, Positions& x, Positions& v);

// After the step: puts each scripted vertex exactly at its position at `t` (no drift).
void place_scripted_pins(const std::vector<PinScript>& scripts, double t, Positions& x);

}  // namespace weft
