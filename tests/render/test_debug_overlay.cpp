#include "render/debug_overlay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/mesh_generators.hpp"
#include "render/world_view.hpp"

namespace weft {
namespace {

bool contains(const Eigen::AlignedBox3d& outer, const Aabb& inner) {
  return outer.contains(Eigen::AlignedBox3d(inner.lower, inner.upper));
}

// Depth 0 is the root; each deeper level covers every triangle with more, smaller boxes, down
// to the leaves.
TEST(DebugOverlay, BvhBoxesAtDepthCoverEveryTriangle) {
  const TriangleMesh grid = make_grid(9, 9, 1.0, 1.0, GridTriangulation::regular);
  Bvh bvh;
  bvh.build(grid.positions, grid.triangles, 0.01);
  const std::vector<Eigen::AlignedBox3d> root = bvh_boxes_at_depth(bvh, 0);
  ASSERT_EQ(root.size(), 1u);
  EXPECT_TRUE(root[0].min().isApprox(bvh.nodes()[0].box.lower));
  int leaves = 0;
  for (const BvhNode& node : bvh.nodes()) leaves += node.is_leaf();
  std::vector<Eigen::AlignedBox3d> previous_boxes = root;
  size_t previous = 1;
  for (int depth = 1; depth <= 12; ++depth) {
    const std::vector<Eigen::AlignedBox3d> boxes = bvh_boxes_at_depth(bvh, depth);
    EXPECT_GE(boxes.size(), previous);
    // Every box sits inside a box of the level above (its parent, or itself for a leaf).
    for (const Eigen::AlignedBox3d& box : boxes) {
      bool inside = false;
      for (const Eigen::AlignedBox3d& parent : previous_boxes) inside |= parent.contains(box);
      EXPECT_TRUE(inside) << depth;
    }
    for (const Aabb& triangle_box : bvh.triangle_boxes()) {
      bool covered = false;
      for (const Eigen::AlignedBox3d& box : boxes) covered |= contains(box, triangle_box);
      EXPECT_TRUE(covered) << depth;
    }
    previous = boxes.size();
    previous_boxes = boxes;
  }
  EXPECT_EQ(static_cast<int>(previous), leaves);
  EXPECT_GT(leaves, 8);
}

// The four contact kinds have four colours; arrows only where there is an impulse direction.
TEST(DebugOverlay, ContactsColouredByKindWithImpulseArrows) {
  std::set<std::tuple<float, float, float>> colours;
  for (const ContactKind kind : {ContactKind::vertex_face, ContactKind::edge_edge}) {
    for (const ContactPartners partners :
         {ContactPartners::cloth_cloth, ContactPartners::cloth_solid, ContactPartners::soft_body}) {
      const Color c = contact_color(kind, partners);
      colours.insert({c.x(), c.y(), c.z()});
    }
  }
  EXPECT_EQ(colours.size(), 6u);

  std::vector<ContactRecord> contacts(2);
  contacts[0].position = Vec3(1.0, 0.0, 0.0);
  contacts[0].impulse = 0.01;
  contacts[0].normal = Vec3::UnitY();
  contacts[1].impulse = 0.02;  // no normal recorded: a point only
  DebugOverlay overlay;
  add_contacts(overlay, contacts, 100.0, 10.0);
  ASSERT_EQ(overlay.points.size(), 2u);
  ASSERT_EQ(overlay.lines.size(), 3u);  // one shaft, two barbs
  EXPECT_TRUE(overlay.lines[0].to.isApprox(Vec3(1.0, 1.0, 0.0)));
}

// Arrows keep the asked scale while the largest one fits; past that, all shrink by one factor.
TEST(DebugOverlay, ContactArrowScaleCapsTheLargestArrow) {
  // 0.001 N s at 200 m per N s is 0.2 m, under a 0.5 m cap: unchanged.
  EXPECT_DOUBLE_EQ(contact_arrow_scale(0.001, 200.0, 0.5), 200.0);
  // 0.01 N s would be 2 m: the largest arrow is exactly the cap, a half as large one half of it.
  const double scale = contact_arrow_scale(0.01, 200.0, 0.5);
  EXPECT_DOUBLE_EQ(scale * 0.01, 0.5);
  EXPECT_DOUBLE_EQ(scale * 0.005, 0.25);
  // At the cap exactly, and with no impulse at all, the scale stays.
  EXPECT_DOUBLE_EQ(contact_arrow_scale(0.0025, 200.0, 0.5), 200.0);
  EXPECT_DOUBLE_EQ(contact_arrow_scale(0.0, 200.0, 0.5), 200.0);
  // The cap scales with the impulse: ten times the impulse, a tenth of the scale.
  EXPECT_DOUBLE_EQ(contact_arrow_scale(0.1, 200.0, 0.5), 0.1 * scale);
}

// Dense, strong contact: no arrow longer than the cap, and arrows in proportion to their impulses.
TEST(DebugOverlay, DenseContactArrowsStayWithinTheCap) {
  std::vector<ContactRecord> contacts(100);
  for (size_t k = 0; k < contacts.size(); ++k) {
    contacts[k].position = Vec3(0.01 * static_cast<double>(k), 0.0, 0.0);
    contacts[k].normal = Vec3::UnitY();
    contacts[k].impulse = 0.001 * static_cast<double>(k + 1);  // up to 0.1 N s: 20 m at 200 m per N s
  }
  DebugOverlay overlay;
  add_contacts(overlay, contacts, 200.0, 0.05);
  ASSERT_EQ(overlay.lines.size(), 3 * contacts.size());
  double longest = 0.0;
  for (size_t k = 0; k < contacts.size(); ++k) {
    const OverlayLine& shaft = overlay.lines[3 * k];
    const double length = (shaft.to - shaft.from).norm();
    longest = std::max(longest, length);
    EXPECT_NEAR(length, 0.05 * contacts[k].impulse / 0.1, 1e-12) << k;
  }
  EXPECT_NEAR(longest, 0.05, 1e-12);
}

// The overlay built from a world shows boxes and contacts only when switched on.
TEST(DebugOverlay, BuildOverlayFollowsTheSwitches) {
  World world;
  const TriangleMesh grid = make_grid(5, 5, 1.0, 1.0, GridTriangulation::regular);
  ClothModel model;
  model.triangles = grid.triangles;
  model.rest_positions = grid.positions;
  model.mass = Eigen::VectorXd::Ones(grid.num_vertices());
  model.inverse_mass = model.mass;
  world.add_cloth(make_cloth(std::move(model)));
  WorldMeshes meshes;
  update_bvhs(meshes, world);
  std::vector<ContactRecord> contacts(3);

  ViewOptions options;
  options.boxes = false;
  options.contacts = false;
  DebugOverlay plain;
  build_overlay(plain, world, meshes, options, contacts);
  options.boxes = true;
  options.box_depth = 2;
  DebugOverlay boxes;
  build_overlay(boxes, world, meshes, options, contacts);
  EXPECT_EQ(boxes.lines.size(), plain.lines.size() + 12 * bvh_boxes_at_depth(meshes.cloth_bvhs[0], 2).size());
  options.contacts = true;
  DebugOverlay with_contacts;
  build_overlay(with_contacts, world, meshes, options, contacts);
  EXPECT_EQ(with_contacts.points.size(), boxes.points.size() + 3);
}

// The world's contacts: a cloth resting on a plane reports cloth-solid contacts, a vertex-face
// one for every vertex with the plane's normal.
TEST(DebugOverlay, WorldReportsContactsWithTheGround) {
  World world;
  const TriangleMesh grid = make_grid(4, 4, 1.0, 1.0, GridTriangulation::regular);
  ClothModel model;
  model.triangles = grid.triangles;
  model.rest_positions = grid.positions;
  model.rest_positions.row(2) = model.rest_positions.row(1);
  model.rest_positions.row(1).setConstant(0.001);  // flat, 1 mm above the ground
  model.mass = Eigen::VectorXd::Constant(grid.num_vertices(), 0.01);
  model.inverse_mass = model.mass.cwiseInverse();
  world.add_cloth(make_cloth(std::move(model)));
  world.add_collider(Collider{});  // the plane y = 0
  EXPECT_TRUE(world.contacts().empty());
  world.step();
  ASSERT_EQ(static_cast<int>(world.contacts().size()), world.last_step_stats().contacts);
  std::set<int> touching;
  for (const ContactRecord& contact : world.contacts()) {
    EXPECT_EQ(contact.partners, ContactPartners::cloth_solid);
    EXPECT_GT(contact.impulse, 0.0);
    EXPECT_NEAR(contact.normal.norm(), 1.0, 1e-12);
    if (contact.kind != ContactKind::vertex_face) continue;
    touching.insert(contact.primitive_a);
    EXPECT_TRUE(contact.normal.isApprox(Vec3::UnitY()));  // out of the floor, onto the vertex
  }
  // Every cloth vertex rests within the thickness (one on the floor square's diagonal touches
  // both of its triangles).
  EXPECT_EQ(touching.size(), 16u);
}

}  // namespace
}  // namespace weft
