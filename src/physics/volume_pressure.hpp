#pragma once
// Pressure in closed soft bodies: the enclosed volume V = sum_t x0 . (x1 x x2)/6 over the
// outward-facing (counter-clockwise seen from outside) triangles, and an energy E(V). The caller
// assembles dE/dx = E'(V) dV/dx and d2E/dx2 = E''(V) dV/dx dV/dx^T + E'(V) d2V/dx2; the first
// term is a dense rank-one matrix over the body's vertices (keep it as a low-rank term).
#include "core/math.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

// Signed volume of the tetrahedron (origin, x0, x1, x2), V_t = x0 . (x1 x x2)/6; summed over a
// closed outward mesh it is the enclosed volume, independent of the origin. Fills the gradient
// (x1 x x2, x2 x x0, x0 x x1)/6 and the Hessian (zero diagonal blocks, off-diagonal blocks
// d2V/dx0dx1 = -[x2]x/6, d2V/dx0dx2 = [x1]x/6, d2V/dx1dx2 = -[x0]x/6, [a]x b = a x b) when not null.
double triangle_signed_volume(const Vec3& x0, const Vec3& x1, const Vec3& x2, Vector9d* gradient,
                              Matrix9d* hessian);

// Energy of the total volume: E(V) = bulk_modulus/2 (V - target)^2/target with
// target = pressure_scale * rest_volume, so the gas pressure -dE/dV = bulk_modulus (target - V)/target
// pushes outwards when the body is squeezed below its target (pressure_scale > 1 inflates it).
struct PressureLaw {
  double bulk_modulus = 1e4;   // Pa
  double rest_volume = 1.0;    // m^3, from the rest shape
  double pressure_scale = 1.0;  // target / rest volume
};

// Returns E(V) and fills dE/dV and d2E/dV2 when not null. Throws std::invalid_argument when the
// target volume is not positive.
double pressure_energy(double volume, const PressureLaw& law, double* dE_dV, double* d2E_dV2);

// The pressure term of a closed soft body (off unless `enabled`).
struct PressureTerm {
  PressureLaw law;
  bool enabled = false;
};

// Enclosed volume of the closed, outward-oriented mesh.
double enclosed_volume(const Triangles& triangles, const Positions& x);

// Pressure energy E(V(x)); adds dE/dx = E'(V) dV/dx to `gradient` and, to `hessian`, the part
// E'(V) d2V/dx2 assembled triangle by triangle (PSD-projected if asked). The dense rank-one part
// E''(V) dV/dx dV/dx^T is PSD and left out of the Newton matrix: the step stays a descent
// direction and the line search keeps it safe, at the price of linear convergence when pressure
// dominates.
double evaluate_pressure(const PressureTerm& term, const Triangles& triangles, const Positions& x,
                         Positions* gradient, SparseHessian* hessian, int stencil, bool project);

}  // namespace weft
