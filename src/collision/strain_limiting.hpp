#pragma once
// Strain limiting on the candidate motion (Provot 1995; Bridson, Marino & Fedkiw 2003): after the
// proximity impulses and after each round's CCD impulses (before the impact zones), every cloth
// edge stretched past (1 + max_strain) times its rest length at the end of the step is shortened
// to that length, its two ends moving along the edge in inverse proportion to their masses (so
// linear momentum is kept and a pinned end does not move). Gauss-Seidel sweeps over the edges, each correction
// of x_end by dx adding dx/h to the velocity. It bounds the stretch that contact impulses in
// dense multi-layer contact leave behind; continuous detection runs on the limited motion, so the
// no-intersection guarantee is unchanged.
#include <vector>

#include "collision/collision_step.hpp"

namespace weft {

// An edge within this fraction of its limit counts as limited (the sweeps stop there).
constexpr double strain_limit_slack = 1e-3;

// The length past which an edge of this rest length counts as over a limit of max_strain: the one
// threshold the limiter's sweeps, the impact zones and the phase's count of edges left over share.
inline double over_limit_length(double rest, double max_strain) {
  return (1.0 + max_strain) * (1.0 + strain_limit_slack) * rest;
}

struct StrainLimitResult {
  int sweeps = 0;                      // sweeps run
  int corrected_edges = 0;             // edge corrections, summed over the sweeps
  double largest_strain_before = 0.0;  // largest |x_j - x_i| / rest - 1 over the edges, before
};

// Limits the stretch of the edges step.edges(:, e) with rest_length[e] > 0 (edges of zero or
// negative rest length, e.g. collider edges, are skipped). Sweeps until no edge exceeds the bound
// by more than 1e-3 of it, at most max_sweeps times.
StrainLimitResult limit_edge_strain(CollisionStep& step, const std::vector<double>& rest_length,
                                    double max_strain, int max_sweeps);

// The strain limit as the impact zones read it: edge e is over it when some end has finite mass
// and its end-of-step length exceeds both (1 + max_strain) rest_length[e] (to the limiter's
// slack of 1e-3) and its start-of-step length, which a rigid motion keeps.
struct StrainBound {
  const std::vector<double>& rest_length;
  double max_strain;
};
bool edge_over_limit(const CollisionStep& step, const StrainBound& bound, int e);

}  // namespace weft
