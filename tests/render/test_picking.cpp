#include "render/picking.hpp"

#include <random>

#include <gtest/gtest.h>

#include "core/mesh_generators.hpp"

namespace weft {
namespace {

Cloth grid_cloth(double z) {
  const TriangleMesh grid = make_grid(6, 6, 1.0, 1.0, GridTriangulation::alternating);
  ClothModel model;
  model.triangles = grid.triangles;
  model.rest_positions = grid.positions;
  model.rest_positions.row(2).array() += z;
  model.mass = Eigen::VectorXd::Ones(grid.num_vertices());
  model.inverse_mass = model.mass;
  return make_cloth(std::move(model));
}

// Normalised device coordinates of a point.
Eigen::Vector2d to_ndc(const OrbitCamera& camera, double aspect, const Vec3& point) {
  const Eigen::Vector4d clip = (camera.projection_matrix(aspect) * camera.view_matrix()).cast<double>() *
                               Eigen::Vector4d(point.x(), point.y(), point.z(), 1.0);
  return clip.head<2>() / clip.w();
}

// The ray through a vertex's projection picks that vertex, from the front and from an angle.
TEST(Picking, RayThroughAVertexPicksIt) {
  const std::vector<Cloth> cloths{grid_cloth(0.0)};
  const double aspect = 16.0 / 9.0;
  for (const double orbit : {0.0, 120.0}) {
    OrbitCamera camera;
    camera.frame(Eigen::AlignedBox3d(Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, 0.0)), aspect);
    camera.orbit(orbit, 0.3 * orbit);
    for (const int vertex : {0, 7, 14, 21, 35}) {
      // A point a little way towards the triangle's inside, so the ray hits the cloth.
      const Vec3 target = 0.97 * cloths[0].state.x.col(vertex);
      const Eigen::Vector2d ndc = to_ndc(camera, aspect, target);
      const std::optional<VertexPick> pick = pick_vertex(cloths, camera_ray(camera, aspect, ndc.x(), ndc.y()));
      ASSERT_TRUE(pick.has_value()) << "orbit " << orbit << ", vertex " << vertex;
      EXPECT_EQ(pick->cloth, 0);
      EXPECT_EQ(pick->vertex, vertex) << "orbit " << orbit;
      EXPECT_LT((pick->hit - target).norm(), 1e-5);
    }
  }
}

// Of two cloths one behind the other the nearer is picked; a ray past both picks nothing.
TEST(Picking, NearestClothWinsAndMissesReturnNothing) {
  const std::vector<Cloth> cloths{grid_cloth(-1.0), grid_cloth(0.5)};
  const Ray ray{Vec3(0.01, 0.02, 5.0), Vec3(0.0, 0.0, -1.0)};
  const std::optional<VertexPick> pick = pick_vertex(cloths, ray);
  ASSERT_TRUE(pick.has_value());
  EXPECT_EQ(pick->cloth, 1);
  EXPECT_NEAR(pick->distance, 4.5, 1e-12);
  EXPECT_FALSE(pick_vertex(cloths, Ray{Vec3(3.0, 0.0, 5.0), Vec3(0.0, 0.0, -1.0)}).has_value());
  EXPECT_FALSE(pick_vertex(cloths, Ray{Vec3(0.0, 0.0, 5.0), Vec3(0.0, 0.0, 1.0)}).has_value());
}

TEST(Picking, ViewPlaneKeepsTheGrabbedDepth) {
  const Vec3 grabbed(0.2, 0.1, -0.3);
  const Vec3 view(0.0, 0.0, -1.0);
  const Vec3 point = point_on_view_plane(Ray{Vec3(0.0, 0.0, 4.0), Vec3(0.1, 0.05, -1.0).normalized()}, grabbed, view);
  EXPECT_NEAR(point.z(), grabbed.z(), 1e-12);
}

// Picking through the hierarchies finds exactly what testing every triangle finds, on crumpled
// cloths from random rays (hits, misses, rays starting between the cloths).
TEST(Picking, ThroughTheHierarchyEqualsEveryTriangle) {
  std::vector<Cloth> cloths{grid_cloth(-0.2), grid_cloth(0.3)};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Bvh> bvhs(cloths.size());
  for (size_t c = 0; c < cloths.size(); ++c) {
    Positions& x = cloths[c].state.x;
    for (int i = 0; i < x.cols(); ++i) x.col(i) += 0.15 * Vec3(uniform(random), uniform(random), uniform(random));
    bvhs[c].build(x, cloths[c].model.triangles, 0.0);
  }
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Ray ray{Vec3(0.6 * uniform(random), 0.6 * uniform(random), 2.0 * uniform(random)),
                  Vec3(0.3 * uniform(random), 0.3 * uniform(random), uniform(random)).normalized()};
    const std::optional<VertexPick> direct = pick_vertex(cloths, ray);
    const std::optional<VertexPick> through = pick_vertex(cloths, ray, &bvhs);
    ASSERT_EQ(direct.has_value(), through.has_value()) << "ray " << k;
    if (!direct) continue;
    ++hits;
    EXPECT_EQ(through->cloth, direct->cloth);
    EXPECT_EQ(through->vertex, direct->vertex);
    EXPECT_EQ(through->distance, direct->distance);
  }
  EXPECT_GT(hits, 200);  // the rays do meet the cloths
}

}  // namespace
}  // namespace weft
