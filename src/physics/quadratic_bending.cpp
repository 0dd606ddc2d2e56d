#include "physics/quadratic_bending.hpp"

#include <cmath>
#include <stdexcept>

namespace weft {

namespace {

// A triangle's height over the edge must exceed this fraction of |e| (as in hinge_bending.cpp).
constexpr double min_relative_height = 1e-8;

// cot of the angle between u and v.
double cotangent(const Vec3& u, const Vec3& v) { return u.dot(v) / u.cross(v).norm(); }

}  // namespace

QuadraticHinge quadratic_hinge_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  const Vec3 e = x1 - x0;
  const double l2 = e.squaredNorm();
  const double twice_area1 = e.cross(x2 - x0).norm();
  const double twice_area2 = e.cross(x3 - x0).norm();
  const double threshold = min_relative_height * l2;  // |n| = h |e| > tol |e|^2
  if (!(l2 > 0.0) || !(twice_area1 > threshold) || !(twice_area2 > threshold)) {
    throw std::invalid_argument("quadratic_hinge_rest: degenerate edge or triangle");
  }
  const double cot_a1 = cotangent(e, x2 - x0), cot_a2 = cotangent(e, x3 - x0);
  const double cot_b1 = cotangent(-e, x2 - x1), cot_b2 = cotangent(-e, x3 - x1);
  QuadraticHinge hinge;
  hinge.weights << cot_b1 + cot_b2, cot_a1 + cot_a2, -(cot_a1 + cot_b1), -(cot_a2 + cot_b2);
  hinge.scale = 3.0 / (0.5 * (twice_area1 + twice_area2));
  return hinge;
}

double quadratic_bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                const QuadraticHinge& hinge, double stiffness, Vector12d* gradient) {
  const Vec3 curvature = quadratic_hinge_curvature(x0, x1, x2, x3, hinge);
  const double k = stiffness * hinge.scale;
  if (gradient) {
    const Vec3 scaled = (2.0 * k) * curvature;
    for (int i = 0; i < 4; ++i) gradient->segment<3>(3 * i) = hinge.weights[i] * scaled;
  }
  return k * curvature.squaredNorm();
}

Eigen::Matrix4d quadratic_bending_hessian_coefficients(const QuadraticHinge& hinge, double stiffness) {
  return (2.0 * stiffness * hinge.scale) * hinge.weights * hinge.weights.transpose();
}

}  // namespace weft
