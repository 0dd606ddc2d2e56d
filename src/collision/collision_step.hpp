#pragma once
// The flat interface of the collision response: one step's motion over a combined vertex index
// space (every cloth, soft body and collider mesh together), and the settings of the response.
// Whatever broad phase produced the candidate pairs, the response reads and corrects only this.
#include <vector>

#include "core/math.hpp"

namespace weft {

struct CollisionStep {
  const Positions& x_start;  // positions at the start of the step (3 x n_vertices)
  Positions& x_end;          // candidate positions at the end of the step, corrected (3 x n_vertices)
  Positions& velocity;       // velocities at the end of the step (3 x n_vertices); every
                             // correction of x_end by h dv adds dv here too
  const Eigen::VectorXd& inverse_mass;  // (n_vertices); 0 = pinned, scripted or collider (infinite mass)
  const Triangles& triangles;           // (3 x n_triangles)
  const Eigen::Matrix2Xi& edges;        // (2 x n_edges)
  double time_step;                     // h (s)
  // (n_vertices) or null: 1 for the infinite-mass vertices that the impact zones' last fail-safe
  // may hold at their start (cloth pins, whose script then lags), 0 for those it cannot (colliders).
  const std::vector<char>* holdable = nullptr;
};

struct ResponseSettings {
  double thickness = 0.005;             // m; proximity response keeps pairs this far apart
  double static_friction = 0.4;         // Coulomb coefficient below which sliding stops
  double kinetic_friction = 0.3;        // Coulomb coefficient while sliding
  double repulsion_stiffness = 1000.0;  // N/m; spring of the repulsion impulse (BFA 2002 section 7.2)
  double ccd_tolerance = 1e-6;          // m; proximity accepted at a coplanar time (eta)
  double ccd_separation = 0.1;          // fraction of the thickness a CCD impulse restores as a gap
  int max_ccd_passes = 8;               // detection + impulse passes before impact zones
  int max_impact_zone_passes = 64;      // detection + zone passes before everything involved stops
  // N/m; implicit Euler's contact penalty (0: off). Its normal impulse over the step,
  // h kappa (thickness - distance), joins the proximity impulse in bounding Coulomb friction.
  double penalty_stiffness = 0.0;
  // Collider contacts in the solve (a cloth-collider pair only): kappa = ratio m / h^2, so the
  // penalty's velocity change ratio (thickness - distance) / h joins the bound too.
  double collider_contact_ratio = 0.0;
};

}  // namespace weft
