#include "collision/untangling.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/bvh_traversal.hpp"
#include "collision/primitive_queries.hpp"

namespace weft {

void Untangler::set_mesh(const Triangles& triangles, const std::vector<int>& vertex_mesh) {
  num_vertices_ = static_cast<int>(vertex_mesh.size());
  triangles_ = triangles;
  vertex_mesh_ = vertex_mesh;
  const int num_meshes =
      vertex_mesh.empty() ? 0 : *std::max_element(vertex_mesh.begin(), vertex_mesh.end()) + 1;
  mesh_size_.assign(static_cast<size_t>(num_meshes), 0);
  for (const int mesh : vertex_mesh) ++mesh_size_[mesh];
  topology_ = build_topology(triangles, num_vertices_);
  vertex_incidence<2>(topology_.edges, num_vertices_, vertex_edge_start_, vertex_edges_);
  edge_entries_ = segment_entries(topology_.edges, 0);
  crossings_.clear();
}

const std::vector<EdgeThroughTriangle>& Untangler::find_crossings(const Positions& x) {
  crossings_.clear();
  if (triangles_.cols() == 0) return crossings_;
  triangle_bvh_.build(x, triangles_, 0.0);
  edge_bvh_.build(x, edge_entries_, 0.0);
  const int num_threads = std::max(1, omp_get_max_threads());
  if (static_cast<int>(thread_crossings_.size()) < num_threads) thread_crossings_.resize(num_threads);
  for (auto& list : thread_crossings_) list.clear();
  const Eigen::Matrix2Xi& edges = topology_.edges;
  auto visit = [&](int thread, int e, int t) {
    const int a = edges(0, e);
    const int b = edges(1, e);
    for (int k = 0; k < 3; ++k) {
      if (triangles_(k, t) == a || triangles_(k, t) == b) return;
    }
    const auto crossing = edge_triangle_crossing(x.col(a), x.col(b), x.col(triangles_(0, t)),
                                                 x.col(triangles_(1, t)), x.col(triangles_(2, t)));
    if (crossing) thread_crossings_[thread].push_back({e, t, *crossing});
  };
  bvh_traversal::visit_overlapping_pairs<false>(edge_bvh_, triangle_bvh_, nullptr, buffers_, num_threads,
                                                visit);
  for (const auto& list : thread_crossings_) crossings_.insert(crossings_.end(), list.begin(), list.end());
  std::sort(crossings_.begin(), crossings_.end(),
            [](const EdgeThroughTriangle& p, const EdgeThroughTriangle& q) {
              return p.edge != q.edge ? p.edge < q.edge : p.triangle < q.triangle;
            });
  return crossings_;
}

double Untangler::push_through(int v, const Positions& x, const Vec3& direction, double reach, double margin,
                               int pierced_mesh) {
  const Vec3 from = x.col(v);
  const Vec3 to = from + reach * direction;
  Aabb box;
  box.grow(from);
  box.grow(to);
  find_triangles_in_box(triangle_bvh_, box, box_triangles_);
  double nearest = std::numeric_limits<double>::infinity();
  for (const int t : box_triangles_) {
    if (vertex_mesh_[triangles_(0, t)] != pierced_mesh) continue;
    if (triangles_(0, t) == v || triangles_(1, t) == v || triangles_(2, t) == v) continue;
    const auto crossing = edge_triangle_crossing(from, to, x.col(triangles_(0, t)), x.col(triangles_(1, t)),
                                                 x.col(triangles_(2, t)));
    if (crossing) nearest = std::min(nearest, crossing->s * reach);
  }
  return std::isfinite(nearest) ? nearest + margin : -1.0;
}

bool Untangler::grow_side(int start, const Positions& x, const Eigen::VectorXd& inverse_mass,
                          const Eigen::VectorXd& margin, const EdgeTriangleCrossing& plane, double towards,
                          int pierced_mesh, size_t cap) {
  side_.clear();
  side_push_.clear();
  ++visit_mark_;
  const Vec3 direction = towards * plane.normal;
  // Signed height above the crossing's plane, positive on the side the push goes to.
  auto height = [&](int v) { return towards * plane.normal.dot(x.col(v) - plane.point); };
  auto reach = [&](int v) { return 2.0 * std::abs(height(v)) + 4.0 * margin(v); };

  // The start always moves: through the surface when the ray meets it, else past the plane.
  double start_push = push_through(start, x, direction, reach(start), margin(start), pierced_mesh);
  if (start_push < 0.0) start_push = margin(start) - height(start);
  if (inverse_mass(start) == 0.0) return false;
  visited_[start] = visit_mark_;
  side_.push_back(start);
  side_push_.push_back(start_push);
  for (size_t next = 0; next < side_.size(); ++next) {
    const int v = side_[next];
    for (int k = vertex_edge_start_[v]; k < vertex_edge_start_[v + 1]; ++k) {
      const int e = vertex_edges_[k];
      if (cut_[e]) continue;
      const int w = topology_.edges(0, e) == v ? topology_.edges(1, e) : topology_.edges(0, e);
      if (visited_[w] == visit_mark_ || moving_[w] || frozen_[w]) continue;
      visited_[w] = visit_mark_;
      if (height(w) >= 0.0) continue;  // already on the side the push goes to
      const double push = push_through(w, x, direction, reach(w), margin(w), pierced_mesh);
      if (push < 0.0) continue;  // not behind the pierced surface: the side ends here
      if (inverse_mass(w) == 0.0) return false;
      side_.push_back(w);
      side_push_.push_back(push);
      if (side_.size() > cap) return false;
    }
  }
  return true;
}

int Untangler::find_root(int v) {
  while (parent_[v] != v) {
    parent_[v] = parent_[parent_[v]];
    v = parent_[v];
  }
  return v;
}

UntanglePass Untangler::plan_pushes(const Positions& x, const Eigen::VectorXd& inverse_mass,
                                    const Eigen::VectorXd& margin, Positions& displacement) {
  displacement.setZero(3, num_vertices_);
  UntanglePass pass;
  pass.crossings = static_cast<int>(crossings_.size());
  if (crossings_.empty()) return pass;
  const Eigen::Matrix2Xi& edges = topology_.edges;
  cut_.assign(static_cast<size_t>(edges.cols()), 0);
  for (const EdgeThroughTriangle& c : crossings_) cut_[c.edge] = 1;
  moving_.assign(static_cast<size_t>(num_vertices_), 0);
  frozen_.assign(static_cast<size_t>(num_vertices_), 0);
  visited_.assign(static_cast<size_t>(num_vertices_), 0);
  visit_mark_ = 0;

  // Pieces of the surfaces between the cuts; a crossing whose ends lie in different pieces is on
  // a contour that separates them, and the smaller piece is the one that passed through.
  parent_.resize(static_cast<size_t>(num_vertices_));
  for (int v = 0; v < num_vertices_; ++v) parent_[v] = v;
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    if (cut_[e]) continue;
    const int ra = find_root(edges(0, e));
    const int rb = find_root(edges(1, e));
    if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
  }
  piece_size_.assign(static_cast<size_t>(num_vertices_), 0);
  for (int v = 0; v < num_vertices_; ++v) ++piece_size_[find_root(v)];
  // Separating crossings first, smallest piece first; then the others in list order.
  order_.clear();
  for (size_t k = 0; k < crossings_.size(); ++k) {
    const int ra = find_root(edges(0, crossings_[k].edge));
    const int rb = find_root(edges(1, crossings_[k].edge));
    const int key = ra != rb ? std::min(piece_size_[ra], piece_size_[rb]) : num_vertices_ + 1;
    order_.push_back({key, static_cast<int>(k)});
  }
  std::sort(order_.begin(), order_.end());

  for (const auto& [key, index] : order_) {
    const EdgeThroughTriangle& c = crossings_[index];
    const int a = edges(0, c.edge);
    const int b = edges(1, c.edge);
    if (moving_[a] || moving_[b] || frozen_[a] || frozen_[b]) continue;
    bool triangle_moves = false;
    for (int k = 0; k < 3; ++k) triangle_moves = triangle_moves || moving_[triangles_(k, c.triangle)];
    if (triangle_moves) continue;
    const int pierced_mesh = vertex_mesh_[triangles_(0, c.triangle)];
    const double height_a = c.crossing.normal.dot(x.col(a) - c.crossing.point);
    const double height_b = c.crossing.normal.dot(x.col(b) - c.crossing.point);
    const double towards_b = height_b > 0.0 ? 1.0 : -1.0;
    const double towards_a = height_a > 0.0 ? 1.0 : -1.0;
    const size_t cap = static_cast<size_t>(settings.max_side_fraction * mesh_size_[vertex_mesh_[a]]);
    const bool separating = key <= num_vertices_;
    // A separating crossing moves the smaller piece's side (the other's when that one cannot
    // move); any other moves the smaller of its two sides.
    const bool b_first = separating && piece_size_[find_root(b)] < piece_size_[find_root(a)];
    const int first = b_first ? b : a;
    const int second = b_first ? a : b;
    const double towards_first = b_first ? towards_a : towards_b;
    const double towards_second = b_first ? towards_b : towards_a;
    bool found = grow_side(first, x, inverse_mass, margin, c.crossing, towards_first, pierced_mesh, cap);
    Vec3 direction = towards_first * c.crossing.normal;
    if (found) {
      best_side_ = side_;
      best_push_ = side_push_;
    }
    if (!found || !separating) {
      const size_t cap_second = found ? side_.size() - 1 : cap;
      if (grow_side(second, x, inverse_mass, margin, c.crossing, towards_second, pierced_mesh, cap_second)) {
        found = true;
        best_side_ = side_;
        best_push_ = side_push_;
        direction = towards_second * c.crossing.normal;
      }
    }
    if (!found) continue;

    for (size_t i = 0; i < best_side_.size(); ++i) {
      const int v = best_side_[i];
      moving_[v] = 1;
      displacement.col(v) = best_push_[i] * direction;
      pass.largest_push = std::max(pass.largest_push, best_push_[i]);
    }
    pass.moved_vertices += static_cast<int>(best_side_.size());
    for (int k = 0; k < 3; ++k) frozen_[triangles_(k, c.triangle)] = 1;
    ++pass.sides;
  }
  return pass;
}

}  // namespace weft
