#include "render/orbit_camera.hpp"

#include <algorithm>
#include <cmath>

namespace weft {

namespace {

constexpr double radians_per_pixel = 0.006;
constexpr double max_pitch = 1.55;  // just short of straight up or down, where yaw degenerates
constexpr double zoom_per_step = 0.88;

}  // namespace

void OrbitCamera::frame(const Eigen::AlignedBox3d& box, double aspect) {
  if (box.isEmpty()) return;
  target_ = box.center();
  // The bounding sphere must fit the narrower of the two fields of view.
  const double radius = std::max(0.5 * box.diagonal().norm(), 1e-3);
  const double half_vertical = 0.5 * vertical_fov_;
  const double half_horizontal = std::atan(std::tan(half_vertical) * std::max(aspect, 1e-3));
  distance_ = 1.05 * radius / std::sin(std::min(half_vertical, half_horizontal));
}

void OrbitCamera::keep_in_view(const Eigen::AlignedBox3d& box, double aspect) {
  if (box.isEmpty()) return;
  const Eigen::Vector3d backward = direction();
  const Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(backward).normalized();
  const Eigen::Vector3d up = backward.cross(right);
  const double tan_vertical = std::tan(0.5 * vertical_fov_) / 1.15;
  const double tan_horizontal = std::tan(0.5 * vertical_fov_) * std::max(aspect, 1e-3) / 1.15;
  // A point p is in view when |p . right| <= depth tan and |p . up| <= depth tan, with
  // depth = distance - p . backward (p relative to the target): a least distance per corner.
  double needed = distance_;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d p = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)) - target_;
    const double along = p.dot(backward);
    needed = std::max(needed, std::abs(p.dot(right)) / tan_horizontal + along);
    needed = std::max(needed, std::abs(p.dot(up)) / tan_vertical + along);
  }
  set_distance(needed);
}

void OrbitCamera::set_angles(double yaw, double pitch) {
  yaw_ = yaw;
  pitch_ = std::clamp(pitch, -max_pitch, max_pitch);
}

void OrbitCamera::set_distance(double distance) { distance_ = std::clamp(distance, 1e-3, 1e5); }

void OrbitCamera::orbit(double dx_pixels, double dy_pixels) {
  yaw_ -= radians_per_pixel * dx_pixels;
  pitch_ = std::clamp(pitch_ + radians_per_pixel * dy_pixels, -max_pitch, max_pitch);
}

void OrbitCamera::pan(double dx_pixels, double dy_pixels, double viewport_height) {
  // Metres per pixel at the target's depth.
  const double scale = 2.0 * distance_ * std::tan(0.5 * vertical_fov_) / std::max(viewport_height, 1.0);
  const Eigen::Vector3d forward = -direction();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  target_ += scale * (-dx_pixels * right + dy_pixels * up);
}

void OrbitCamera::zoom(double wheel_steps) {
  distance_ = std::clamp(distance_ * std::pow(zoom_per_step, wheel_steps), 1e-3, 1e5);
}

Eigen::Vector3d OrbitCamera::direction() const {
  return {std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_), std::cos(pitch_) * std::cos(yaw_)};
}

Eigen::Vector3d OrbitCamera::eye() const { return target_ + distance_ * direction(); }

Eigen::Matrix4f OrbitCamera::view_matrix() const {
  // The usual look-at: rows are the camera's right, up and backward axes.
  const Eigen::Vector3d backward = direction();
  const Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(backward).normalized();
  const Eigen::Vector3d up = backward.cross(right);
  const Eigen::Vector3d eye_position = eye();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = right.transpose();
  view.block<1, 3>(1, 0) = up.transpose();
  view.block<1, 3>(2, 0) = backward.transpose();
  view(0, 3) = -right.dot(eye_position);
  view(1, 3) = -up.dot(eye_position);
  view(2, 3) = -backward.dot(eye_position);
  return view.cast<float>();
}

Eigen::Matrix4f OrbitCamera::projection_matrix(double aspect) const {
  // Near and far follow the distance so depth precision suits any scene size.
  const double near_plane = 0.01 * distance_;
  const double far_plane = 100.0 * distance_;
  const double f = 1.0 / std::tan(0.5 * vertical_fov_);
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = f / std::max(aspect, 1e-6);
  projection(1, 1) = f;
  projection(2, 2) = (far_plane + near_plane) / (near_plane - far_plane);
  projection(2, 3) = 2.0 * far_plane * near_plane / (near_plane - far_plane);
  projection(3, 2) = -1.0;
  return projection.cast<float>();
}

}  // namespace weft
