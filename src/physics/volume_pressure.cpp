#include "physics/volume_pressure.hpp"

#include <stdexcept>

namespace weft {

namespace {

Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace

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

}  // namespace weft
