#pragma once
// Tiny collision scenes for the response tests: squares of two triangles in one combined index
// space, every vertex-face and edge-edge pair as candidates (a brute-force broad phase), and an
// independent segment-triangle intersection test to check the end state.
#include <cmath>
#include <vector>

#include "collision/collision_step.hpp"
#include "collision/contact_pairs.hpp"
#include "core/math.hpp"

namespace weft::test {

struct CollisionScene {
  Positions x_start = Positions(3, 0);
  Positions x_end = Positions(3, 0);
  Positions velocity = Positions(3, 0);
  Eigen::VectorXd inverse_mass = Eigen::VectorXd(0);
  Triangles triangles = Triangles(3, 0);
  Eigen::Matrix2Xi edges = Eigen::Matrix2Xi(2, 0);
  double h = 0.01;

  int add_vertex(const Vec3& x, const Vec3& v, double inverse_mass_value) {
    const int n = static_cast<int>(x_start.cols());
    x_start.conservativeResize(3, n + 1);
    velocity.conservativeResize(3, n + 1);
    inverse_mass.conservativeResize(n + 1);
    x_start.col(n) = x;
    velocity.col(n) = v;
    inverse_mass[n] = inverse_mass_value;
    x_end = x_start + h * velocity;
    return n;
  }
  void add_triangle(int a, int b, int c) {
    triangles.conservativeResize(3, triangles.cols() + 1);
    triangles.col(triangles.cols() - 1) = Vec3i(a, b, c);
  }
  void add_edge(int a, int b) {
    edges.conservativeResize(2, edges.cols() + 1);
    edges.col(edges.cols() - 1) = Eigen::Vector2i(a, b);
  }
  // A horizontal square (normal +z) of side `size` centred at `center`, turned by `angle` about z,
  // moving with `v`: 4 vertices, 2 triangles, 5 edges.
  void add_square(const Vec3& center, double size, double angle, const Vec3& v, double inverse_mass_value) {
    const Mat3 rotation = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
    int ids[4];
    const double corners[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
    for (int k = 0; k < 4; ++k) {
      ids[k] = add_vertex(center + rotation * Vec3(corners[k][0] * size, corners[k][1] * size, 0.0), v,
                          inverse_mass_value);
    }
    add_triangle(ids[0], ids[1], ids[2]);
    add_triangle(ids[0], ids[2], ids[3]);
    for (int k = 0; k < 4; ++k) add_edge(ids[k], ids[(k + 1) % 4]);
    add_edge(ids[0], ids[2]);
  }
  void set_velocity(int vertex, const Vec3& v) {
    velocity.col(vertex) = v;
    x_end.col(vertex) = x_start.col(vertex) + h * v;
  }
  CollisionStep step() { return {x_start, x_end, velocity, inverse_mass, triangles, edges, h}; }

  std::vector<VertexFacePair> all_vertex_faces() const {
    std::vector<VertexFacePair> pairs;
    for (int v = 0; v < x_start.cols(); ++v) {
      for (int t = 0; t < triangles.cols(); ++t) pairs.push_back({v, t});
    }
    return pairs;
  }
  std::vector<EdgeEdgePair> all_edge_edges() const {
    std::vector<EdgeEdgePair> pairs;
    for (int a = 0; a < edges.cols(); ++a) {
      for (int b = a + 1; b < edges.cols(); ++b) pairs.push_back({a, b});
    }
    return pairs;
  }
  Vec3 momentum(const Positions& v) const {
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < v.cols(); ++k) {
      if (inverse_mass[k] > 0.0) sum += v.col(k) / inverse_mass[k];
    }
    return sum;
  }
};

// Whether segment (p, q) meets triangle (a, b, c): signed volumes on both sides of the plane,
// then the crossing point inside all three edges (Moller-Trumbore style, written out here).
inline bool segment_hits_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double dp = n.dot(p - a);
  const double dq = n.dot(q - a);
  if ((dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || dp == dq) return false;
  const Vec3 x = p + (dp / (dp - dq)) * (q - p);
  const double s0 = n.dot((b - a).cross(x - a));
  const double s1 = n.dot((c - b).cross(x - b));
  const double s2 = n.dot((a - c).cross(x - c));
  return s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0;
}

// Number of (edge, triangle) pairs without a shared vertex that intersect at positions x.
inline int count_intersections(const Positions& x, const Triangles& triangles, const Eigen::Matrix2Xi& edges) {
  int count = 0;
  for (int e = 0; e < edges.cols(); ++e) {
    for (int t = 0; t < triangles.cols(); ++t) {
      const auto tri = triangles.col(t);
      const int i = edges(0, e);
      const int j = edges(1, e);
      if ((tri.array() == i).any() || (tri.array() == j).any()) continue;
      if (segment_hits_triangle(x.col(i), x.col(j), x.col(tri[0]), x.col(tri[1]), x.col(tri[2]))) ++count;
    }
  }
  return count;
}

}  // namespace weft::test
