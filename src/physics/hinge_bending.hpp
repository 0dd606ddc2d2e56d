#pragma once
// Dihedral-angle bending on a hinge (discrete shells, Grinspun et al. 2003):
//   E = stiffness * weight * (theta - rest_angle)^2,  weight = 3 |e|^2/(A1 + A2) at rest,
// with the exact gradient (Bridson et al. 2003) and the exact Hessian (in the spirit of
// Tamstorf & Grinspun 2013, obtained by differentiating that gradient wing by wing).
//
// Hinge layout (MeshTopology::hinges): (x0, x1) is the shared edge, x2 is opposite in the
// triangle (x0, x1, x2) and x3 in the triangle (x1, x0, x3), both counter-clockwise seen from the
// front. theta in (-pi, pi] is the angle from the first triangle's normal to the second's about
// e = x1 - x0: 0 when flat, positive when the hinge is convex seen from the front (a mountain:
// the wings fold away from the normal side; every edge of an outward-facing box is +pi/2),
// negative when concave (a valley).
#include "core/math.hpp"

namespace weft {

struct HingeRest {
  double rest_angle;  // theta at rest (rad)
  double weight;      // 3 |e|^2/(A1 + A2) at rest (dimensionless)
};

// Rest angle and weight of a hinge; throws std::invalid_argument if the edge or either triangle
// is degenerate (zero length or zero area to round-off).
HingeRest hinge_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

// theta = atan2((n1 x n2) . e/|e|, n1 . n2) with n1 = e x (x2 - x0), n2 = (x3 - x0) x e.
// Returns 0 where a normal or the edge vanishes.
double dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

// Energy stiffness * weight * d^2 with d = theta - rest_angle wrapped into [-pi, pi] (the energy is
// continuous across theta = +-pi and jumps only at theta = rest_angle + pi). Fills the gradient
// and the exact Hessian (vertices x0..x3 stacked) when not null. Where a triangle's height over
// the edge is below 1e-8 |e| (or |e| = 0) the angle is ill-defined: the energy is still returned
// but the gradient and Hessian are zero.
double hinge_bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                            const HingeRest& rest, double stiffness, Vector12d* gradient, Matrix12d* hessian);

// The same energy and gradient with the Gauss-Newton Hessian, the exact one's PSD part
// 2 k grad(theta) grad(theta)^T (the dropped part is 2 k d hess(theta), small near the rest
// angle), in factored form: H = curvature * angle_gradient angle_gradient^T (curvature = 2 k),
// for assembly without the 12x12 matrix.
struct HingeGaussNewton {
  double energy;
  Vector12d gradient;
  Vector12d angle_gradient;  // zero where the angle is ill-defined
  double curvature;
};
HingeGaussNewton hinge_bending_gauss_newton(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                           const HingeRest& rest, double stiffness);

}  // namespace weft
