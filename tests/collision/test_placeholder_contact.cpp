// Placeholder contact: vertices end outside every analytic collider by the thickness, lose
// their approaching normal velocity, and Coulomb friction stops slow sliding.
#include "collision/placeholder_contact.hpp"

#include <gtest/gtest.h>

namespace weft {
namespace {

Cloth single_vertex(const Vec3& position, const Vec3& velocity) {
  ClothModel model;
  model.rest_positions = position;
  model.mass = Eigen::VectorXd::Ones(1);
  model.inverse_mass = Eigen::VectorXd::Ones(1);
  model.thickness = 0.01;
  Cloth cloth = make_cloth(std::move(model));
  cloth.state.v.col(0) = velocity;
  return cloth;
}

TEST(Collider, SignedDistancesOfEachShape) {
  Vec3 normal;
  Collider plane;
  plane.shape = ColliderShape::plane;
  EXPECT_DOUBLE_EQ(signed_distance(plane, Vec3(3, -0.25, 1), normal), -0.25);
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.radius = 1.0;
  EXPECT_DOUBLE_EQ(signed_distance(sphere, Vec3(0, 0, 3), normal), 2.0);
  EXPECT_TRUE(normal.isApprox(Vec3::UnitZ()));
  Collider box;
  box.shape = ColliderShape::box;
  box.half_extents = Vec3(1, 2, 3);
  EXPECT_DOUBLE_EQ(signed_distance(box, Vec3(0, 1.5, 0), normal), -0.5);
  EXPECT_TRUE(normal.isApprox(Vec3::UnitY()));
  EXPECT_DOUBLE_EQ(signed_distance(box, Vec3(4, 6, 0), normal), 5.0);  // corner region: (3, 4) away
  EXPECT_TRUE(normal.isApprox(Vec3(0.6, 0.8, 0)));
}

TEST(PlaceholderContact, ProjectsOutOfEveryShapeAndStopsApproach) {
  std::vector<Collider> shapes(3);
  shapes[0].shape = ColliderShape::plane;
  shapes[1].shape = ColliderShape::sphere;
  shapes[1].center = Vec3(5, 0, 0);
  shapes[2].shape = ColliderShape::box;
  shapes[2].center = Vec3(-5, 0, 0);
  const Vec3 inside[3] = {Vec3(0, -0.2, 0), Vec3(5.1, 0.2, 0), Vec3(-5.1, 0.3, 0.1)};
  for (int k = 0; k < 3; ++k) {
    Cloth cloth = single_vertex(inside[k], Vec3(0.0, -2.0, 0.0));
    const std::vector<Collider> one{shapes[k]};
    EXPECT_EQ(resolve_placeholder_contacts(cloth, one, 0.01), 1) << k;
    Vec3 normal;
    EXPECT_NEAR(signed_distance(shapes[k], cloth.state.x.col(0), normal), cloth.model.thickness, 1e-12) << k;
    EXPECT_GE(cloth.state.v.col(0).dot(normal), -1e-12) << k;
  }
}

TEST(PlaceholderContact, CoulombFrictionSticksOrSlides) {
  std::vector<Collider> ground(1);
  ground[0].friction = 0.5;
  // Normal speed 2 removed: tangential speed drops by 0.5 * 2 = 1.
  Cloth sliding = single_vertex(Vec3(0, 0, 0), Vec3(3.0, -2.0, 0.0));
  resolve_placeholder_contacts(sliding, ground, 0.01);
  EXPECT_NEAR(sliding.state.v(0, 0), 2.0, 1e-12);
  EXPECT_NEAR(sliding.state.v(1, 0), 0.0, 1e-12);
  Cloth sticking = single_vertex(Vec3(0, 0, 0), Vec3(0.5, -2.0, 0.0));
  resolve_placeholder_contacts(sticking, ground, 0.01);
  EXPECT_EQ(sticking.state.v.col(0), Vec3::Zero());
}

TEST(PlaceholderContact, PinnedVerticesAreLeftAlone) {
  std::vector<Collider> ground(1);
  Cloth cloth = single_vertex(Vec3(0, -1, 0), Vec3::Zero());
  cloth.model.inverse_mass.setZero();
  EXPECT_EQ(resolve_placeholder_contacts(cloth, ground, 0.01), 0);
  EXPECT_EQ(cloth.state.x.col(0), Vec3(0, -1, 0));
}

}  // namespace
}  // namespace weft
