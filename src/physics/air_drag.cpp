#include "physics/air_drag.hpp"

namespace weft {

double air_drag_matrix(const Vec3& x0, const Vec3& x1, const Vec3& x2, double normal_coefficient,
                       double tangential_coefficient, Mat3& drag) {
  const Vec3 cross = (x1 - x0).cross(x2 - x0);
  const double twice_area = cross.norm();
  if (!(twice_area > 0.0)) {
    drag.setZero();
    return 0.0;
  }
  const Vec3 n = cross / twice_area;
  drag = (normal_coefficient - tangential_coefficient) * n * n.transpose() + tangential_coefficient * Mat3::Identity();
  return 0.5 * twice_area;
}

void air_drag_forces(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                     const Vec3& wind, double normal_coefficient, double tangential_coefficient, Vector9d& force,
                     Matrix9d* velocity_jacobian) {
  Mat3 drag;
  const double area = air_drag_matrix(x0, x1, x2, normal_coefficient, tangential_coefficient, drag);

  // Per-vertex force -(A/3) D u.
  const Vec3 u = (v0 + v1 + v2) / 3.0 - wind;
  const Vec3 f = -(area / 3.0) * (drag * u);
  force << f, f, f;
  // du/dv_j = I/3 for every vertex j.
  if (velocity_jacobian) {
    const Mat3 block = -(area / 9.0) * drag;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) velocity_jacobian->block<3, 3>(3 * i, 3 * j) = block;
    }
  }
}

void add_air_drag_forces(const AirDragTerm& term, const Triangles& triangles, const Positions& x, const Positions& v,
                         Positions& force) {
  Vector9d element_force;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const int i0 = triangles(0, t), i1 = triangles(1, t), i2 = triangles(2, t);
    air_drag_forces(x.col(i0), x.col(i1), x.col(i2), v.col(i0), v.col(i1), v.col(i2), term.wind,
                    term.normal_coefficient, term.tangential_coefficient, element_force, nullptr);
    force.col(i0) += element_force.segment<3>(0);
    force.col(i1) += element_force.segment<3>(3);
    force.col(i2) += element_force.segment<3>(6);
  }
}

double evaluate_air_drag_dissipation(const AirDragTerm& term, const Triangles& triangles, const Positions& x_start,
                                     const Positions& x, double h, Positions* gradient, SparseHessian* hessian,
                                     int stencil) {
  double energy = 0.0;
  Mat3 drag;
  Matrix9d element_hessian;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const int i0 = triangles(0, t), i1 = triangles(1, t), i2 = triangles(2, t);
    const double area = air_drag_matrix(x_start.col(i0), x_start.col(i1), x_start.col(i2), term.normal_coefficient,
                                        term.tangential_coefficient, drag);
    const Vec3 u = (x.col(i0) + x.col(i1) + x.col(i2) - x_start.col(i0) - x_start.col(i1) - x_start.col(i2)) /
                       (3.0 * h) - term.wind;
    const Vec3 drag_u = drag * u;
    energy += 0.5 * h * area * u.dot(drag_u);
    if (gradient) {
      // dP/dx_i = h A D (u - w) du/dx_i with du/dx_i = I/(3h).
      const Vec3 g = (area / 3.0) * drag_u;
      gradient->col(i0) += g;
      gradient->col(i1) += g;
      gradient->col(i2) += g;
    }
    if (hessian) {
      const Mat3 block = (area / (9.0 * h)) * drag;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) element_hessian.block<3, 3>(3 * a, 3 * b) = block;
      }
      hessian->add_element<3>(stencil, static_cast<int>(t), element_hessian);
    }
  }
  return energy;
}

}  // namespace weft
