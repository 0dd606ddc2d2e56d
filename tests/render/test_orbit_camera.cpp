#include "render/orbit_camera.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace weft {
namespace {

Eigen::Vector3f to_ndc(const Eigen::Matrix4f& view_projection, const Eigen::Vector3d& point) {
  const Eigen::Vector4f clip = view_projection * Eigen::Vector4f(point.x(), point.y(), point.z(), 1.0f);
  EXPECT_GT(clip.w(), 0.0f);
  return clip.head<3>() / clip.w();
}

TEST(OrbitCamera, FrameKeepsEveryBoxCornerInView) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1.0, 0.0, -3.0), Eigen::Vector3d(2.0, 1.0, 0.0));
  for (const double aspect : {16.0 / 9.0, 1.0, 0.5}) {
    OrbitCamera camera;
    camera.frame(box, aspect);
    EXPECT_TRUE(camera.target().isApprox(box.center()));
    const Eigen::Matrix4f view_projection = camera.projection_matrix(aspect) * camera.view_matrix();
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3f ndc =
          to_ndc(view_projection, box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
      EXPECT_LE(ndc.head<3>().cwiseAbs().maxCoeff(), 1.0f) << "aspect " << aspect << ", corner " << corner;
    }
  }
}

TEST(OrbitCamera, KeepInViewMovesBackUntilTheBoxFitsWithItsBorderAndNeverCloser) {
  // A view set close to an off-centre target, as a scene's "view" may be for a later frame.
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1.0, 0.9, -1.0), Eigen::Vector3d(1.0, 1.1, 1.0));
  for (const double aspect : {16.0 / 9.0, 1.0, 0.5}) {
    OrbitCamera camera;
    camera.set_angles(0.5, 0.4);
    camera.set_target(Eigen::Vector3d(0.0, 0.1, 0.0));
    camera.set_distance(1.0);
    camera.keep_in_view(box, aspect);
    EXPECT_TRUE(camera.target().isApprox(Eigen::Vector3d(0.0, 0.1, 0.0)));
    const Eigen::Matrix4f view_projection = camera.projection_matrix(aspect) * camera.view_matrix();
    float largest = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3f ndc =
          to_ndc(view_projection, box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
      largest = std::max(largest, ndc.head<2>().cwiseAbs().maxCoeff());
    }
    // Within the 15% border, and touching it: no farther back than it must be.
    EXPECT_NEAR(largest, 1.0f / 1.15f, 1e-3f) << "aspect " << aspect;
    const double fitted = camera.distance();
    camera.keep_in_view(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.01)),
                        aspect);
    EXPECT_EQ(camera.distance(), fitted) << "a box already in view does not bring the camera closer";
  }
}

TEST(OrbitCamera, ViewPutsTargetStraightAhead) {
  OrbitCamera camera;
  camera.frame(Eigen::AlignedBox3d(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(2, 3, 4)), 1.0);
  camera.orbit(40.0, -25.0);
  const Eigen::Vector4f target = camera.view_matrix() * Eigen::Vector4f(1.5f, 2.5f, 3.5f, 1.0f);
  EXPECT_NEAR(target.x(), 0.0f, 1e-4f);
  EXPECT_NEAR(target.y(), 0.0f, 1e-4f);
  EXPECT_NEAR(target.z(), -camera.distance(), 1e-4f);
}

// A scene's view places the camera outright: yaw 0 puts the eye on +z, 90 degrees on +x; the
// pitch raises it and stops short of the pole.
TEST(OrbitCamera, SetAnglesTargetAndDistancePlaceTheEye) {
  OrbitCamera camera;
  camera.set_target(Eigen::Vector3d(1.0, 2.0, 3.0));
  camera.set_distance(4.0);
  camera.set_angles(0.0, 0.0);
  EXPECT_TRUE(camera.eye().isApprox(Eigen::Vector3d(1.0, 2.0, 7.0)));
  camera.set_angles(0.5 * 3.14159265358979, 0.0);
  EXPECT_TRUE(camera.eye().isApprox(Eigen::Vector3d(5.0, 2.0, 3.0)));
  camera.set_angles(0.0, 0.5236);  // 30 degrees up
  EXPECT_NEAR(camera.eye().y(), 2.0 + 4.0 * std::sin(0.5236), 1e-12);
  camera.set_angles(0.0, 2.0);
  EXPECT_LT(camera.pitch(), 1.5708);
  EXPECT_NEAR(camera.distance(), 4.0, 1e-12);
}

TEST(OrbitCamera, OrbitKeepsDistanceZoomChangesIt) {
  OrbitCamera camera;
  const double distance = camera.distance();
  camera.orbit(120.0, 300.0);
  EXPECT_NEAR((camera.eye() - camera.target()).norm(), distance, 1e-9);
  camera.zoom(2.0);
  EXPECT_LT(camera.distance(), distance);
  camera.zoom(-4.0);
  EXPECT_GT(camera.distance(), distance);
}

TEST(OrbitCamera, PanMovesTargetAcrossTheView) {
  OrbitCamera camera;
  const Eigen::Vector3d eye_to_target = camera.target() - camera.eye();
  const Eigen::Vector3d before = camera.target();
  camera.pan(30.0, -12.0, 720.0);
  const Eigen::Vector3d moved = camera.target() - before;
  EXPECT_GT(moved.norm(), 0.0);
  EXPECT_NEAR(moved.dot(eye_to_target.normalized()), 0.0, 1e-9);
}

}  // namespace
}  // namespace weft
