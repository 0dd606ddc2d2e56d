#include "physics/hinge_bending.hpp"

#include <cmath>
#include <stdexcept>

#include "physics/psd_projection.hpp"

namespace weft {

namespace {

// A triangle's height over the edge must exceed this fraction of |e| for theta to be used.
constexpr double min_relative_height = 1e-8;

// Edge, opposite-vertex offsets and unnormalised normals of a hinge.
struct HingeFrame {
  Vec3 e;     // x1 - x0
  Vec3 u1;    // x2 - x0
  Vec3 u2;    // x3 - x0
  Vec3 n1;    // e x u1, |n1| = 2 A1
  Vec3 n2;    // u2 x e, |n2| = 2 A2
  double l2;  // |e|^2
  double theta;
  bool degenerate;
};

HingeFrame hinge_frame(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  HingeFrame h;
  h.e = x1 - x0;
  h.u1 = x2 - x0;
  h.u2 = x3 - x0;
  h.n1 = h.e.cross(h.u1);
  h.n2 = h.u2.cross(h.e);
  h.l2 = h.e.squaredNorm();
  // |n| = h |e| for the height h of the opposite vertex: h > tol |e|  <=>  |n|^2 > tol^2 |e|^4.
  const double threshold = min_relative_height * min_relative_height * h.l2 * h.l2;
  h.degenerate = !(h.l2 > 0.0) || !(h.n1.squaredNorm() > threshold) || !(h.n2.squaredNorm() > threshold);
  // n1 x n2 is parallel to e: sin(theta) |n1| |n2| = (n1 x n2) . e/|e|.
  const double l = std::sqrt(h.l2);
  h.theta = std::atan2(h.n1.cross(h.n2).dot(h.e), l * h.n1.dot(h.n2));
  return h;
}

// One wing of the hinge: the triangle (x0, x1, p) with n = sign e x u, u = p - x0.
// The angle gradient is a m on x0, x1 and p with m = |e| n/|n|^2 (the unit normal over the
// height) and a = (1 - s, s, -1), s = u.e/|e|^2 the projection of p along the edge. This adds
// d(a_v m)/dx_w = a_v dm/dx_w + m (da_v/dx_w)^T to the angle Hessian (rows v, columns w).
void add_wing_hessian(const Vec3& e, const Vec3& u, const Vec3& n, double sign, int p, double l2,
                      Matrix12d& h) {
  const double n_squared = n.squaredNorm();
  const double l = std::sqrt(l2);
  const double c = l / n_squared;
  const Vec3 n_unit = n / std::sqrt(n_squared);
  const Vec3 m = c * n;
  const double s = u.dot(e) / l2;

  // dm = n/|n|^2 d|e| + c (I - 2 n^ n^T) dn, dn = sign (de x u + e x du), de = dx1 - dx0,
  // du = dp - dx0; (I - 2 n^ n^T) [a]x = [a]x - 2 n^ (n^ x a)^T.
  Mat3 dm[3];
  dm[1] = (n / n_squared) * (e / l).transpose() -
          sign * c * (cross_matrix(u) - 2.0 * n_unit * n_unit.cross(u).transpose());
  dm[2] = sign * c * (cross_matrix(e) - 2.0 * n_unit * n_unit.cross(e).transpose());
  dm[0] = -(dm[1] + dm[2]);
  // ds = (e.du + (u - 2 s e).de)/|e|^2.
  Vec3 ds[3];
  ds[1] = (u - 2.0 * s * e) / l2;
  ds[2] = e / l2;
  ds[0] = -(ds[1] + ds[2]);

  const int index[3] = {0, 3, 3 * p};
  for (int w = 0; w < 3; ++w) {
    const int col = index[w];
    const Mat3 m_ds = m * ds[w].transpose();
    h.block<3, 3>(0, col) += (1.0 - s) * dm[w] - m_ds;
    h.block<3, 3>(3, col) += s * dm[w] + m_ds;
    h.block<3, 3>(3 * p, col) -= dm[w];
  }
}

}  // namespace

HingeRest hinge_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  const HingeFrame h = hinge_frame(x0, x1, x2, x3);
  if (h.degenerate) throw std::invalid_argument("hinge_rest: degenerate edge or triangle");
  const double area_sum = 0.5 * (h.n1.norm() + h.n2.norm());
  return HingeRest{h.theta, 3.0 * h.l2 / area_sum};
}

double dihedral_angle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  return hinge_frame(x0, x1, x2, x3).theta;
}

namespace {

// What every form of the hinge's derivatives starts from: the frame, the wrapped angle
// difference d, k = stiffness * weight and the angle gradient (zero when degenerate).
struct HingeState {
  HingeFrame frame;
  double delta;
  double k;
};

HingeState hinge_state(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, const HingeRest& rest,
                       double stiffness) {
  HingeState state{hinge_frame(x0, x1, x2, x3), 0.0, stiffness * rest.weight};
  state.delta = state.frame.theta - rest.rest_angle;
  if (state.delta > pi) {
    state.delta -= 2.0 * pi;
  } else if (state.delta < -pi) {
    state.delta += 2.0 * pi;
  }
  return state;
}

// Angle gradient (Bridson et al. 2003): -m1 on x2, -m2 on x3, and on the edge vertices the
// split that keeps it free of net force and torque; m = |e| n/|n|^2, s = (p - x0).e/|e|^2.
Vector12d angle_gradient(const HingeFrame& h) {
  const double l = std::sqrt(h.l2);
  const Vec3 m1 = (l / h.n1.squaredNorm()) * h.n1;
  const Vec3 m2 = (l / h.n2.squaredNorm()) * h.n2;
  const double s1 = h.u1.dot(h.e) / h.l2;
  const double s2 = h.u2.dot(h.e) / h.l2;
  Vector12d gradient;
  gradient << (1.0 - s1) * m1 + (1.0 - s2) * m2, s1 * m1 + s2 * m2, -m1, -m2;
  return gradient;
}

}  // namespace

double hinge_bending_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                            const HingeRest& rest, double stiffness, Vector12d* gradient, Matrix12d* hessian) {
  const HingeState state = hinge_state(x0, x1, x2, x3, rest, stiffness);
  const HingeFrame& h = state.frame;
  const double k = state.k, delta = state.delta;
  const double energy = k * delta * delta;
  if (!gradient && !hessian) return energy;
  if (h.degenerate) {
    if (gradient) gradient->setZero();
    if (hessian) hessian->setZero();
    return energy;
  }
  const Vector12d a = angle_gradient(h);
  if (gradient) *gradient = (2.0 * k * delta) * a;

  // H = 2 k (grad theta grad theta^T + delta hess theta); hess theta is the sum of the wings'.
  if (hessian) {
    Matrix12d angle_hessian = Matrix12d::Zero();
    add_wing_hessian(h.e, h.u1, h.n1, 1.0, 2, h.l2, angle_hessian);
    add_wing_hessian(h.e, h.u2, h.n2, -1.0, 3, h.l2, angle_hessian);
    hessian->noalias() = (2.0 * k) * a * a.transpose();
    *hessian += (k * delta) * (angle_hessian + angle_hessian.transpose());
  }
  return energy;
}

HingeGaussNewton hinge_bending_gauss_newton(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3,
                                           const HingeRest& rest, double stiffness) {
  const HingeState state = hinge_state(x0, x1, x2, x3, rest, stiffness);
  HingeGaussNewton result{state.k * state.delta * state.delta, Vector12d::Zero(), Vector12d::Zero(), 2.0 * state.k};
  if (state.frame.degenerate) return result;
  result.angle_gradient = angle_gradient(state.frame);
  result.gradient = (2.0 * state.k * state.delta) * result.angle_gradient;
  return result;
}

}  // namespace weft
