#pragma once
// Shared machinery of the continuous tests (BFA 2002 section 6): four points moving linearly over
// the step are coplanar where the cubic f(t) = (a + t da) x (b + t db) . (c + t dc) vanishes.
// Rather than trusting closed-form roots, [0, 1] is split where f' and f'' change sign so f is
// monotone on each piece, and sign-based bisection brackets where |f| is below a round-off
// tolerance. A degenerate cubic (quadratic, linear, zero motion, coplanar motion) needs no
// special case: an identically small f gives the whole of [0, 1].
#include <array>
#include <cmath>

#include "core/math.hpp"

namespace weft {

struct CoplanarityCubic {
  std::array<double, 4> coefficients;  // f(t) = c0 + c1 t + c2 t^2 + c3 t^3
  double tolerance;                    // |f| below this counts as coplanar (round-off scale)
};

struct TimeInterval {
  double begin;
  double end;
};

// Coefficients of f for edges a, b from a common origin and the offset c of the fourth point,
// each with its change over the step (da = a_end - a_start, ...).
CoplanarityCubic coplanarity_cubic(const Vec3& a, const Vec3& da, const Vec3& b, const Vec3& db,
                                   const Vec3& c, const Vec3& dc);

double evaluate(const CoplanarityCubic& cubic, double t);

// False when |f| > tolerance all over [0, 1] (a cheap, conservative test on the Bernstein
// coefficients), so that near_coplanar_intervals would find nothing. The continuous tests run it
// first, and near_coplanar_intervals only on the cubics it keeps: most candidate pairs, whose
// four points are not coplanar at any time of the step, are settled by it.
bool may_vanish(const CoplanarityCubic& cubic);

// Disjoint intervals of [0, 1], in increasing order, on which |f| <= tolerance (widened by the
// bisection so that no such time is left out). Returns how many were written (at most 3).
int near_coplanar_intervals(const CoplanarityCubic& cubic, std::array<TimeInterval, 3>& intervals);

// False when a distance that is d_start at t = 0, d_end at t = 1 and `lipschitz`-Lipschitz in
// between cannot come within eta over [0, 1]: d(t) >= max(d_start - L t, d_end - L (1 - t)) >=
// (d_start + d_end - L) / 2. The continuous tests run it after may_vanish: it settles the pairs
// that stay nearly coplanar all step long (neighbours in a flat sheet) but never close. The margin
// covers the round-off of the three inputs.
inline bool may_come_within(double d_start, double d_end, double lipschitz, double eta) {
  return d_start + d_end - lipschitz <= 2.0 * eta + 1e-12 * (d_start + d_end + lipschitz);
}

// Earliest time in [begin, end] at which distance_at(t) <= eta, by conservative advancement:
// distance_at is `lipschitz`-Lipschitz in t, so no time closer than eta is skipped. Returns a
// negative value if there is none; after `max_steps` steps it gives up conservatively and
// returns the time reached. A slow, grazing approach converges only geometrically, so the
// default is generous; only pairs inside a near-coplanar interval pay for it.
template <class DistanceAt>
double earliest_proximity(const DistanceAt& distance_at, TimeInterval interval, double eta, double lipschitz,
                          int max_steps = 1000) {
  double t = interval.begin;
  for (int step = 0; step < max_steps; ++step) {
    const double distance = distance_at(t);
    if (distance <= eta) return t;
    if (!(lipschitz > 0.0) || t >= interval.end) return -1.0;
    // No time in [t, t + (distance - eta)/L) can come within eta. Near the crossing the advance
    // falls below the resolution of t; then step to the next representable time, which skips
    // nothing.
    const double advanced = std::min(t + (distance - eta) / lipschitz, interval.end);
    t = advanced > t ? advanced : std::nextafter(t, interval.end);
  }
  return t;
}

}  // namespace weft
