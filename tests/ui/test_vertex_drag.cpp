#include "ui/vertex_drag.hpp"

#include <gtest/gtest.h>

#include "core/mesh_generators.hpp"

namespace weft {
namespace {

World free_cloth_world() {
  const TriangleMesh grid = make_grid(4, 4, 1.0, 1.0, GridTriangulation::regular);
  ClothModel model;
  model.triangles = grid.triangles;
  model.rest_positions = grid.positions;
  model.mass = Eigen::VectorXd::Constant(grid.num_vertices(), 0.01);
  model.inverse_mass = model.mass.cwiseInverse();
  World world;
  world.settings.gravity.setZero();
  world.settings.time_step = 1e-3;
  world.add_cloth(make_cloth(std::move(model)));
  return world;
}

// The spring pulls the grabbed vertex to the cursor's point and leaves the others alone
// (no springs between them here); letting go clears the force.
TEST(VertexDrag, PullsTheGrabbedVertexToTheTarget) {
  World world = free_cloth_world();
  const int vertex = 5;
  const Vec3 target = world.cloths()[0].state.x.col(vertex) + Vec3(0.0, 0.0, 0.2);
  VertexDrag drag;
  drag.begin(0, vertex, target);
  for (int step = 0; step < 1000; ++step) {  // 1 s, many spring periods (w = 25 rad/s)
    drag.apply(world);
    world.step();
  }
  const Cloth& cloth = world.cloths()[0];
  EXPECT_LT((cloth.state.x.col(vertex) - target).norm(), 1e-3);
  EXPECT_TRUE(cloth.state.x.col(0).isApprox(cloth.model.rest_positions.col(0)));
  drag.end(world);
  EXPECT_FALSE(drag.active());
  EXPECT_TRUE(world.external_force(0).isZero(0.0));
}

// A drag that outlives its scene (reloaded with fewer vertices) does nothing.
TEST(VertexDrag, IgnoresAVertexTheWorldNoLongerHas) {
  World world = free_cloth_world();
  VertexDrag drag;
  drag.begin(0, 1000, Vec3::Zero());
  drag.apply(world);
  EXPECT_TRUE(world.external_force(0).isZero(0.0));
  drag.begin(3, 0, Vec3::Zero());
  drag.apply(world);
  drag.end(world);
}

}  // namespace
}  // namespace weft
