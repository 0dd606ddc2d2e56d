#pragma once
// A camera orbiting a target point, y up: turn (yaw, pitch), pan the target, zoom the distance.
// Plain math, no OpenGL: matrices come out in OpenGL's conventions (right-handed, clip z in [-1, 1]).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace weft {

class OrbitCamera {
 public:
  // Looks at the box's centre from the current direction, far enough to see all of it at `aspect`.
  void frame(const Eigen::AlignedBox3d& box, double aspect);

  // Places the camera outright: yaw about +y (0 puts the eye on +z), pitch above the horizontal
  // (clamped short of straight up or down), both in radians.
  void set_angles(double yaw, double pitch);
  void set_target(const Eigen::Vector3d& target) { target_ = target; }
  void set_distance(double distance);
  // Moves back from the target, keeping it and the angles, until every corner of the box is in
  // view at `aspect` with a 15% border; never moves closer.
  void keep_in_view(const Eigen::AlignedBox3d& box, double aspect);

  // Turns around the target by mouse motion in pixels.
  void orbit(double dx_pixels, double dy_pixels);
  // Moves the target with the mouse so the point under it follows; `viewport_height` in pixels.
  void pan(double dx_pixels, double dy_pixels, double viewport_height);
  // Moves closer (positive `wheel_steps`) or further.
  void zoom(double wheel_steps);

  Eigen::Vector3d eye() const;
  const Eigen::Vector3d& target() const { return target_; }
  double distance() const { return distance_; }
  double yaw() const { return yaw_; }
  double pitch() const { return pitch_; }
  double vertical_fov() const { return vertical_fov_; }

  Eigen::Matrix4f view_matrix() const;
  Eigen::Matrix4f projection_matrix(double aspect) const;

 private:
  // Unit vector from the target towards the eye.
  Eigen::Vector3d direction() const;

  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();
  double distance_ = 5.0;         // m, eye to target
  double yaw_ = 0.4;              // rad about +y, 0 looks along -z
  double pitch_ = 0.3;            // rad above the horizontal
  double vertical_fov_ = 0.7854;  // rad (45 degrees)
};

}  // namespace weft
