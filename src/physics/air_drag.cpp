#include "physics/air_drag.hpp"

namespace weft {

void air_drag_forces(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                     const Vec3& wind, double normal_coefficient, double tangential_coefficient, Vector9d& force,
                     Matrix9d* velocity_jacobian) {
  const Vec3 cross = (x1 - x0).cross(x2 - x0);
  const double twice_area = cross.norm();
  if (!(twice_area > 0.0)) {
    force.setZero();
    if (velocity_jacobian) velocity_jacobian->setZero();
    return;
  }
  const Vec3 n = cross / twice_area;
  const double area = 0.5 * twice_area;

  // Per-vertex force -(A/3) D u with the drag matrix D = cn n n^T + ct (I - n n^T).
  const Mat3 drag = (normal_coefficient - tangential_coefficient) * n * n.transpose() +
                    tangential_coefficient * Mat3::Identity();
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

}  // namespace weft
