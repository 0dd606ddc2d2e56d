#pragma once
// The scalar laws of contact inside the solve (the barrier response, sim/barrier_contact.hpp).
//
// Barrier: the log barrier of Li et al. 2020 (IPC) on the unsigned distance d of a pair,
//   b(d) = -(d - dhat)^2 ln(d / dhat)  for 0 < d < dhat,  0 for d >= dhat,
// C2 at dhat, infinite at d = 0, so a pair whose distance stays positive along the solve's
// motion never passes through. The energy is kappa b(d), kappa in N/m.
//
// Friction: IPC's lagged, smoothed Coulomb dissipation on the tangential displacement u of a
// contact over the step, mu lambda f0(|u|), with f0(y) = -y^3 / (3 eps^2) + y^2 / eps + eps / 3
// for y < eps and y beyond: f0' = f1 = 2y / eps - y^2 / eps^2 (then 1) rises from 0 to 1 over
// the displacement eps (a slip speed times h), which stands for static friction.

namespace weft {

struct BarrierValue {
  double value = 0.0;   // b(d)
  double first = 0.0;   // b'(d) (<= 0)
  double second = 0.0;  // b''(d) (>= 0)
};

// b and its derivatives at d (> 0) for the radius dhat (> 0); all zero at d >= dhat.
BarrierValue log_barrier(double d, double dhat);

struct FrictionValue {
  double value = 0.0;   // f0(y)
  double first = 0.0;   // f1(y) = f0'(y), in [0, 1]
  double ratio = 0.0;   // f1(y) / y (finite at y = 0: 2 / eps)
  double second = 0.0;  // f1'(y) (>= 0)
};

// f0 and its derivatives at the tangential displacement y >= 0 for the smoothing eps > 0.
FrictionValue smoothed_friction(double y, double eps);

}  // namespace weft
