#include "physics/volume_pressure.hpp"

#include <stdexcept>

#include "physics/psd_projection.hpp"

namespace weft {

double triangle_signed_volume(const Vec3& x0, const Vec3& x1, const Vec3& x2, Vector9d* gradient,
                              Matrix9d* hessian) {
  const Vec3 x1_x2 = x1.cross(x2);
  if (gradient) *gradient << x1_x2 / 6.0, x2.cross(x0) / 6.0, x0.cross(x1) / 6.0;
  if (hessian) {
    // d(x1 x x2)/dx1 = -[x2]x, d(x1 x x2)/dx2 = [x1]x, d(x2 x x0)/dx2 = -[x0]x; symmetric.
    const Mat3 a01 = -cross_matrix(x2) / 6.0;
    const Mat3 a02 = cross_matrix(x1) / 6.0;
    const Mat3 a12 = -cross_matrix(x0) / 6.0;
    *hessian << Mat3::Zero(), a01, a02, a01.transpose(), Mat3::Zero(), a12, a02.transpose(), a12.transpose(),
        Mat3::Zero();
  }
  return x0.dot(x1_x2) / 6.0;
}

double pressure_energy(double volume, const PressureLaw& law, double* dE_dV, double* d2E_dV2) {
  const double target = law.pressure_scale * law.rest_volume;
  if (!(target > 0.0)) throw std::invalid_argument("pressure_energy: target volume must be positive");
  const double excess = volume - target;
  if (dE_dV) *dE_dV = law.bulk_modulus * excess / target;
  if (d2E_dV2) *d2E_dV2 = law.bulk_modulus / target;
  return 0.5 * law.bulk_modulus * excess * excess / target;
}

double enclosed_volume(const Triangles& triangles, const Positions& x) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    volume += triangle_signed_volume(x.col(triangles(0, t)), x.col(triangles(1, t)), x.col(triangles(2, t)), nullptr,
                                     nullptr);
  }
  return volume;
}

double evaluate_pressure(const PressureTerm& term, const Triangles& triangles, const Positions& x,
                         Positions* gradient, SparseHessian* hessian, int stencil, bool project) {
  const double volume = enclosed_volume(triangles, x);
  double d_energy = 0.0;
  const double energy = pressure_energy(volume, term.law, &d_energy, nullptr);
  if (!gradient && !hessian) return energy;
  Vector9d volume_gradient;
  Matrix9d volume_hessian;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const int i0 = triangles(0, t), i1 = triangles(1, t), i2 = triangles(2, t);
    triangle_signed_volume(x.col(i0), x.col(i1), x.col(i2), gradient ? &volume_gradient : nullptr,
                           hessian ? &volume_hessian : nullptr);
    if (gradient) {
      gradient->col(i0) += d_energy * volume_gradient.segment<3>(0);
      gradient->col(i1) += d_energy * volume_gradient.segment<3>(3);
      gradient->col(i2) += d_energy * volume_gradient.segment<3>(6);
    }
    if (hessian) {
      Matrix9d element = d_energy * volume_hessian;
      if (project) project_to_psd<9>(element);
      hessian->add_element<3>(stencil, static_cast<int>(t), element);
    }
  }
  return energy;
}

}  // namespace weft
