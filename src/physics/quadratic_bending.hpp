#pragma once
// Quadratic bending for a hinge whose rest shape is flat (after Bergou et al. 2006, "A quadratic
// bending model for inextensible surfaces"):
//   E = stiffness * scale * |sum_i w_i x_i|^2,  scale = 3/(A1 + A2) at rest,
// where w are the hinge's cotangent weights at rest. Hinge layout as in hinge_bending.hpp: (x0, x1)
// is the shared edge, x2 is opposite in the triangle (x0, x1, x2), x3 in (x1, x0, x3). With a_k the
// rest angle at x0 and b_k the one at x1 in triangle k (1: the one with x2, 2: the one with x3),
//   w = (cot b1 + cot b2, cot a1 + cot a2, -(cot a1 + cot b1), -(cot a2 + cot b2)).
// The weights sum to zero and annihilate the flat rest positions (and every affine image of them),
// so the energy is zero at rest and invariant under rigid motion. Folding a wing by theta about the
// edge without stretching moves its tip by 2 h sin(theta/2) (h its height over the edge, its weight
// |e|/h), so sum_i w_i x_i has length 2 |e| sin(theta/2) and
//   E = stiffness * weight * 4 sin^2(theta/2)
// with the dihedral model's weight 3 |e|^2/(A1 + A2): the same as its stiffness * weight * theta^2 to
// second order in theta, and the same stiffness in J. It differs from the dihedral model in what
// matters to a solver: the energy is a fixed quadratic form of the positions, so its Hessian
//   d2E/dx_i dx_j = 2 stiffness scale w_i w_j I3
// is constant, positive semi-definite and exact, and its gradient stays bounded as a wing collapses
// (the dihedral angle's gradient grows as 1/height there). It holds only for a flat rest shape.
#include <Eigen/Core>

#include "core/math.hpp"

namespace weft {

struct QuadraticHinge {
  Eigen::Vector4d weights;  // w (dimensionless)
  double scale;             // 3/(A1 + A2) at rest (1/m^2)
};

// Weights and scale from the rest hinge; throws std::invalid_argument if the edge or either triangle
// is degenerate (zero length or zero area to round-off).
QuadraticHinge quadratic_hinge_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

// sum_i w_i x_i: the hinge's curvature vector (m), zero for any flat, unstretched or affinely
// stretched placement of the rest hinge.
inline Vec3 quadratic_hinge_curvature(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                      const QuadraticHinge& hinge) {
  const Eigen::Vector4d& w = hinge.weights;
  return w[0] * x0 + w[1] * x1 + w[2] * x2 + w[3] * x3;
}

// Energy stiffness * scale * |curvature|^2; fills the gradient (vertices x0..x3 stacked) when not
// null: 2 stiffness scale w_i curvature on vertex i.
double quadratic_bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                const QuadraticHinge& hinge, double stiffness, Vector12d* gradient);

// The constant Hessian's 4x4 vertex coefficients: block (i, j) is coefficients(i, j) * I3.
Eigen::Matrix4d quadratic_bending_hessian_coefficients(const QuadraticHinge& hinge, double stiffness);

}  // namespace weft
