#pragma once
// The collision invariants of a World, checked without the collision code: the exact triangle
// intersection check of check/intersection_check over every cloth and collider surface (pairs of
// two colliders aside), and a vertex-in-solid test against the analytic collider shapes from their
// definitions (check/solid_distance: plane half-space, sphere, box, capsule, capped cylinder;
// meshes and open tubes have no inside). A vertex must stay on the side of each solid it started on (outside,
// or inside a drum). Where the scene sets collision.strain_limit, every side of every cloth
// triangle must stay within (1 + strain_limit) times its rest length (to the limiter's 1e-3).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/collider_solid.hpp"
#include "check/intersection_check.hpp"
#include "sim/world.hpp"

namespace weft::testing {

// Signed distance to the collider's solid at time t (negative inside), by the program's own
// check (check/solid_distance.hpp); +inf for shapes without an inside (meshes, open tubes).
inline double reference_signed_distance_at(const Collider& c, const Vec3& p, double t) {
  const std::optional<AnalyticSolid> solid = collider_solid_at(c, t);
  return solid ? reference_signed_distance(*solid, p) : HUGE_VAL;
}

struct InvariantReport {
  int intersecting_pairs = 0;  // non-adjacent triangle pairs that intersect (cloth-cloth, cloth-collider)
  int vertices_crossed = 0;    // cloth vertices on the other side of a solid than at the start
  int edges_over_limit = 0;    // triangle sides longer than (1 + strain_limit) rest, where one is set
  double largest_edge_stretch = 0.0;  // largest side length / rest length over the cloths
  std::string first;           // the first violation, in words
  bool ok() const { return intersecting_pairs == 0 && vertices_crossed == 0 && edges_over_limit == 0; }
};

class SceneInvariants {
 public:
  // Records which side of every solid collider each cloth vertex starts on.
  explicit SceneInvariants(const World& world) {
    for (const Cloth& cloth : world.cloths()) {
      std::vector<int> sides;
      for (const Collider& collider : world.colliders()) {
        for (int i = 0; i < cloth.num_vertices(); ++i) {
          sides.push_back(reference_signed_distance_at(collider, cloth.state.x.col(i), world.time()) < 0.0);
        }
      }
      start_inside_.push_back(std::move(sides));
    }
  }

  InvariantReport check(const World& world) const {
    InvariantReport report;
    std::ostringstream first;
    // Exact triangle-triangle intersections; collider pairs among themselves do not count.
    std::vector<Positions> collider_positions;
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      collider_positions.push_back(world.collider_positions(static_cast<int>(k)));
    }
    std::vector<CheckedMesh> meshes;
    for (const Cloth& cloth : world.cloths()) meshes.push_back({&cloth.state.x, &cloth.model.triangles});
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      meshes.push_back({&collider_positions[k], &world.collider_surface(static_cast<int>(k)).triangles});
    }
    const int num_cloths = static_cast<int>(world.cloths().size());
    for (const TriangleIntersection& hit : find_triangle_intersections(meshes)) {
      if (hit.mesh_a >= num_cloths && hit.mesh_b >= num_cloths) continue;
      if (report.intersecting_pairs++ == 0) {
        first << "t = " << world.time() << ": triangle " << hit.triangle_a << " of mesh " << hit.mesh_a
              << " intersects triangle " << hit.triangle_b << " of mesh " << hit.mesh_b;
      }
    }
    // Vertices that changed side of a solid.
    for (int c = 0; c < num_cloths; ++c) {
      const Cloth& cloth = world.cloths()[c];
      for (size_t k = 0; k < world.colliders().size(); ++k) {
        const Collider& collider = world.colliders()[k];
        for (int i = 0; i < cloth.num_vertices(); ++i) {
          const double distance = reference_signed_distance_at(collider, cloth.state.x.col(i), world.time());
          const bool inside = distance < 0.0;
          if (inside == static_cast<bool>(start_inside_[c][k * cloth.num_vertices() + i])) continue;
          if (report.vertices_crossed++ == 0 && report.intersecting_pairs == 0) {
            first << "t = " << world.time() << ": vertex " << i << " of cloth " << c << " crossed collider "
                  << collider.name << " (signed distance " << distance << ")";
          }
        }
      }
    }
    // Triangle sides against their rest lengths.
    const double limit = world.settings.collision.strain_limit;
    for (int c = 0; c < num_cloths; ++c) {
      const Cloth& cloth = world.cloths()[c];
      const Triangles& triangles = cloth.model.triangles;
      for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
        for (int k = 0; k < 3; ++k) {
          const int a = triangles(k, t), b = triangles((k + 1) % 3, t);
          const double rest = (cloth.model.rest_positions.col(b) - cloth.model.rest_positions.col(a)).norm();
          const double stretch = (cloth.state.x.col(b) - cloth.state.x.col(a)).norm() / rest;
          report.largest_edge_stretch = std::max(report.largest_edge_stretch, stretch);
          if (!(limit > 0.0) || stretch <= (1.0 + limit) * (1.0 + 1.001e-3)) continue;
          if (report.edges_over_limit++ == 0 && report.intersecting_pairs == 0 && report.vertices_crossed == 0) {
            first << "t = " << world.time() << ": edge (" << a << ", " << b << ") of cloth " << c << " at " << stretch
                  << " x its rest length, past the strain limit " << limit;
          }
        }
      }
    }
    report.first = first.str();
    return report;
  }

 private:
  std::vector<std::vector<int>> start_inside_;  // per cloth: collider-major, vertex-minor
};

}  // namespace weft::testing
