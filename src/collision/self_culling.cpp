#include "collision/self_culling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>

#include <omp.h>

namespace weft {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void join(std::vector<int>& parent, int a, int b) { parent[find_root(parent, a)] = find_root(parent, b); }

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double point_segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).norm();
}

// Distance between the segments ab and cd in the plane (0 when they cross or touch).
double segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                        const Eigen::Vector2d& d) {
  const double d1 = cross2(b - a, c - a);
  const double d2 = cross2(b - a, d - a);
  const double d3 = cross2(d - c, a - c);
  const double d4 = cross2(d - c, b - c);
  if (((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))) {
    return 0.0;
  }
  return std::min(std::min(point_segment_distance(a, c, d), point_segment_distance(b, c, d)),
                  std::min(point_segment_distance(c, a, b), point_segment_distance(d, a, b)));
}

}  // namespace

// Whether the triangles order[begin, end) form a topological disk (connected, Euler
// characteristic 1, one boundary loop); if so, `scratch.boundary` holds its boundary edges.
bool SelfCulling::disk_boundary(const std::vector<int>& order, const Triangles& triangles, int begin, int end,
                                DiskScratch& scratch) {
  std::vector<std::array<int, 3>>& edges = scratch.edges;  // (smaller vertex, larger vertex, local triangle)
  std::vector<int>& vertices = scratch.vertices;
  std::vector<int>& triangle_parent = scratch.triangle_parent;
  std::vector<Eigen::Vector2i>& boundary = scratch.boundary;
  std::vector<std::pair<int, int>>& ends = scratch.ends;  // (vertex, boundary edge)
  std::vector<int>& edge_parent = scratch.edge_parent;
  const int num_triangles = end - begin;
  edges.clear();
  vertices.clear();
  boundary.clear();
  for (int i = 0; i < num_triangles; ++i) {
    const int t = order[begin + i];
    for (int c = 0; c < 3; ++c) {
      const int u = triangles(c, t);
      const int v = triangles((c + 1) % 3, t);
      edges.push_back({std::min(u, v), std::max(u, v), i});
      vertices.push_back(u);
    }
  }
  std::sort(edges.begin(), edges.end());
  std::sort(vertices.begin(), vertices.end());
  const int num_vertices = static_cast<int>(std::unique(vertices.begin(), vertices.end()) - vertices.begin());

  // Edges: shared by two triangles (joined), on the boundary (one), or non-manifold (more).
  triangle_parent.resize(num_triangles);
  std::iota(triangle_parent.begin(), triangle_parent.end(), 0);
  int num_edges = 0;
  bool manifold = true;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
    ++num_edges;
    if (j - i == 1) {
      boundary.emplace_back(edges[i][0], edges[i][1]);
    } else if (j - i == 2) {
      join(triangle_parent, edges[i][2], edges[i + 1][2]);
    } else {
      manifold = false;
    }
    i = j;
  }
  if (!manifold || num_vertices - num_edges + num_triangles != 1) return false;
  int components = 0;
  for (int i = 0; i < num_triangles; ++i) components += find_root(triangle_parent, i) == i;
  if (components != 1) return false;

  // One boundary loop: every boundary vertex ends exactly two boundary edges, and the edges
  // joined at their shared vertices form one group.
  ends.clear();
  for (size_t e = 0; e < boundary.size(); ++e) {
    ends.emplace_back(boundary[e].x(), static_cast<int>(e));
    ends.emplace_back(boundary[e].y(), static_cast<int>(e));
  }
  std::sort(ends.begin(), ends.end());
  edge_parent.resize(boundary.size());
  std::iota(edge_parent.begin(), edge_parent.end(), 0);
  bool loop = !boundary.empty();
  for (size_t i = 0; loop && i < ends.size(); i += 2) {
    loop = i + 1 < ends.size() && ends[i + 1].first == ends[i].first &&
           (i + 2 >= ends.size() || ends[i + 2].first != ends[i].first);
    if (loop) join(edge_parent, ends[i].second, ends[i + 1].second);
  }
  if (!loop) return false;
  int loops = 0;
  for (size_t e = 0; e < boundary.size(); ++e)
    loops += find_root(edge_parent, static_cast<int>(e)) == static_cast<int>(e);
  return loops == 1;
}

void SelfCulling::prepare(const Bvh& bvh) {
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const int num_nodes = static_cast<int>(nodes.size());
  const std::vector<int>& order = bvh.triangle_order();
  const Triangles& triangles = bvh.triangles();
  // A subtree's triangles are contiguous in the leaf order: from its leftmost leaf to its
  // rightmost one (children have larger indices, so one backward pass fills every range).
  range_begin_.resize(num_nodes);
  range_end_.resize(num_nodes);
  for (int k = num_nodes - 1; k >= 0; --k) {
    if (nodes[k].is_leaf()) {
      range_begin_[k] = nodes[k].first;
      range_end_[k] = nodes[k].first + nodes[k].count;
    } else {
      range_begin_[k] = range_begin_[k + 1];
      range_end_[k] = range_end_[nodes[k].right];
    }
  }

  // The nodes are analysed independently, in parallel: each thread keeps the boundaries of the
  // disks it found, which are then laid out in node order.
  disk_.assign(num_nodes, 0);
  boundary_start_.assign(num_nodes + 1, 0);
  const int threads = std::max(1, omp_get_max_threads());
  if (static_cast<int>(disk_scratch_.size()) < threads) disk_scratch_.resize(threads);
  for (DiskScratch& scratch : disk_scratch_) {
    scratch.found.clear();
    scratch.found_nodes.clear();
  }
#pragma omp parallel for schedule(dynamic, 16) if (num_nodes > 256)
  for (int k = 0; k < num_nodes; ++k) {
    // Leaves are never culled: the pairs within a leaf are always tested.
    if (nodes[k].is_leaf() || range_end_[k] - range_begin_[k] < 2) continue;
    DiskScratch& scratch = disk_scratch_[omp_get_thread_num()];
    if (!disk_boundary(order, triangles, range_begin_[k], range_end_[k], scratch)) continue;
    disk_[k] = 1;
    scratch.found_nodes.push_back(
        {k, static_cast<int>(scratch.found.size()), static_cast<int>(scratch.boundary.size())});
    scratch.found.insert(scratch.found.end(), scratch.boundary.begin(), scratch.boundary.end());
  }
  for (const DiskScratch& scratch : disk_scratch_) {
    for (const std::array<int, 3>& span : scratch.found_nodes) boundary_start_[span[0] + 1] = span[2];
  }
  for (int k = 0; k < num_nodes; ++k) boundary_start_[k + 1] += boundary_start_[k];
  boundary_.resize(boundary_start_[num_nodes]);
  for (const DiskScratch& scratch : disk_scratch_) {
    for (const std::array<int, 3>& span : scratch.found_nodes) {
      std::copy_n(scratch.found.begin() + span[1], span[2], boundary_.begin() + boundary_start_[span[0]]);
    }
  }
  prepared_build_ = bvh.builds();
}

void SelfCulling::update(const Bvh& bvh, const Positions& x_start, const Positions& x_end, double margin,
                         const SelfCullingSettings& settings) {
  stats_ = SelfCullingStats{};
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const int num_nodes = static_cast<int>(nodes.size());
  culled_.assign(num_nodes, 0);
  if (!settings.enabled || num_nodes == 0) {
    last_.build = -1;
    return;
  }
  if (prepared_build_ != bvh.builds() || static_cast<int>(disk_.size()) != num_nodes) prepare(bvh);

  // What changed since the last update: everything unless it ran on this build with the same
  // margin and cone; else the vertices whose start or end moved (bitwise), the triangles with
  // such a corner and the nodes above those.
  const Triangles& triangles = bvh.triangles();
  const int num_triangles = static_cast<int>(triangles.cols());
  const int num_vertices = static_cast<int>(x_end.cols());
  const bool reuse = last_.build == bvh.builds() && last_.margin == margin &&
                     last_.max_cone_angle == settings.max_cone_angle &&
                     last_.x_start.cols() == num_vertices && last_.x_end.cols() == num_vertices &&
                     static_cast<int>(last_.culled.size()) == num_nodes;
  changed_vertices_.assign(num_vertices, reuse ? 0 : 1);
  if (reuse) {
    const auto differs = [](const Positions& a, const Positions& b, int v) {
      return std::memcmp(a.col(v).data(), b.col(v).data(), 3 * sizeof(double)) != 0;
    };
    for (int v = 0; v < num_vertices; ++v) {
      changed_vertices_[v] = differs(x_start, last_.x_start, v) || differs(x_end, last_.x_end, v);
    }
  }
  changed_triangles_.resize(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    changed_triangles_[t] = changed_vertices_[triangles(0, t)] || changed_vertices_[triangles(1, t)] ||
                            changed_vertices_[triangles(2, t)];
  }

  // Per triangle: the three directions whose cone holds n(t) over the step, and n0 + n1 for the
  // axes (area weighted).
  unit_normals_.resize(3 * static_cast<size_t>(num_triangles));
  degenerate_.resize(num_triangles);
  triangle_axes_.resize(num_triangles);
  axis_sums_.resize(num_nodes);
  std::vector<Vec3>& unit = unit_normals_;
#pragma omp parallel for schedule(static) if (num_triangles > 4096)
  for (int t = 0; t < num_triangles; ++t) {
    if (!changed_triangles_[t]) continue;
    const Vec3 a0 = x_start.col(triangles(0, t)), b0 = x_start.col(triangles(1, t)), c0 = x_start.col(triangles(2, t));
    const Vec3 a1 = x_end.col(triangles(0, t)), b1 = x_end.col(triangles(1, t)), c1 = x_end.col(triangles(2, t));
    const Vec3 e1_start = b0 - a0, e2_start = c0 - a0, e1_end = b1 - a1, e2_end = c1 - a1;
    const std::array<Vec3, 3> normals{e1_start.cross(e2_start), 0.5 * (e1_start.cross(e2_end) + e1_end.cross(e2_start)),
                                      e1_end.cross(e2_end)};
    degenerate_[t] = !(normals[0].squaredNorm() > 0.0) || !(normals[2].squaredNorm() > 0.0);
    triangle_axes_[t] = normals[0] + normals[2];
    for (int j = 0; j < 3; ++j) {
      const double length = normals[j].norm();
      unit[3 * t + j] = length > 0.0 ? Vec3(normals[j] / length) : Vec3::Zero();
    }
  }
  const std::vector<int>& order = bvh.triangle_order();
  changed_nodes_.resize(num_nodes);
  for (int k = num_nodes - 1; k >= 0; --k) {
    if (nodes[k].is_leaf()) {
      bool changed = false;
      for (int i = range_begin_[k]; i < range_end_[k]; ++i) changed = changed || changed_triangles_[order[i]];
      changed_nodes_[k] = changed;
      if (!changed) continue;
      Vec3 sum = Vec3::Zero();
      for (int i = range_begin_[k]; i < range_end_[k]; ++i) sum += triangle_axes_[order[i]];
      axis_sums_[k] = sum;
    } else {
      changed_nodes_[k] = changed_nodes_[k + 1] || changed_nodes_[nodes[k].right];
      if (changed_nodes_[k]) axis_sums_[k] = axis_sums_[k + 1] + axis_sums_[nodes[k].right];
    }
  }

  // Preorder: a culled node's subtree is skipped whole (its within-node task never splits). The
  // nodes above subtrees of at most `small` nodes are walked first; those subtrees (the ones no
  // culled node above holds) then in parallel, each thread with its own contour scratch and counts.
  const double cos_limit = std::cos(settings.max_cone_angle);
  reached_.assign(num_nodes, 0);
  // Tests node k where it is a disk and culls it if it holds (its last decision where nothing in
  // it changed and the last walk reached it); returns the next node of the walk (past k's subtree
  // when culled).
  const auto visit = [&](int k, std::vector<Segment>& segments, SelfCullingStats& stats) {
    reached_[k] = 1;
    if (!disk_[k]) return k + 1;
    ++stats.nodes_tested;
    bool cull = false;
    if (!changed_nodes_[k] && last_.reached[k]) {
      cull = last_.culled[k] != 0;
    } else {
      const double length = axis_sums_[k].norm();
      cull = length > 0.0 && cone_holds(order, k, axis_sums_[k] / length, cos_limit) &&
             contour_simple(k, axis_sums_[k] / length, x_start, x_end, margin, segments);
    }
    if (!cull) return k + 1;
    culled_[k] = 1;
    ++stats.nodes_culled;
    stats.triangles_culled += range_end_[k] - range_begin_[k];
    return nodes[k].next;
  };
  const int threads = std::max(1, omp_get_max_threads());
  if (static_cast<int>(segment_scratch_.size()) < threads) segment_scratch_.resize(threads);
  thread_stats_.assign(threads, SelfCullingStats{});
  const int small = std::max(64, num_nodes / 64);
  subtrees_.clear();
  for (int k = 0; k < num_nodes;) {
    if (nodes[k].next - k <= small) {
      subtrees_.push_back(k);
      k = nodes[k].next;
    } else {
      k = visit(k, segment_scratch_[0], stats_);
    }
  }
  const int num_subtrees = static_cast<int>(subtrees_.size());
#pragma omp parallel for schedule(dynamic, 1) if (num_subtrees > 1 && num_nodes > 1024)
  for (int i = 0; i < num_subtrees; ++i) {
    const int thread = omp_get_thread_num();
    const int end = nodes[subtrees_[i]].next;
    for (int k = subtrees_[i]; k < end;) k = visit(k, segment_scratch_[thread], thread_stats_[thread]);
  }
  for (const SelfCullingStats& stats : thread_stats_) {
    stats_.nodes_tested += stats.nodes_tested;
    stats_.nodes_culled += stats.nodes_culled;
    stats_.triangles_culled += stats.triangles_culled;
  }
  last_.build = bvh.builds();
  last_.margin = margin;
  last_.max_cone_angle = settings.max_cone_angle;
  last_.x_start = x_start;
  last_.x_end = x_end;
  last_.reached.swap(reached_);
  last_.culled = culled_;
}

bool SelfCulling::cone_holds(const std::vector<int>& order, int node, const Vec3& axis, double cos_limit) const {
  for (int i = range_begin_[node]; i < range_end_[node]; ++i) {
    const int t = order[i];
    if (degenerate_[t]) return false;
    for (int j = 0; j < 3; ++j) {
      const Vec3& n = unit_normals_[3 * t + j];
      if (j == 1 && n.squaredNorm() == 0.0) continue;  // the mixed term vanished: n(t) is a sum of n0 and n1
      if (!(n.dot(axis) > cos_limit)) return false;
    }
  }
  return true;
}

bool SelfCulling::contour_simple(int node, const Vec3& axis, const Positions& x_start, const Positions& x_end,
                                 double margin, std::vector<Segment>& segments) const {
  const Vec3 u = axis.unitOrthogonal();
  const Vec3 w = axis.cross(u);
  segments.clear();
  for (int e = boundary_start_[node]; e < boundary_start_[node + 1]; ++e) {
    Segment s;
    s.u = boundary_[e].x();
    s.v = boundary_[e].y();
    const Vec3 p = x_start.col(s.u), q = x_start.col(s.v);
    const Vec3 dp = x_end.col(s.u) - p, dq = x_end.col(s.v) - q;
    s.a = Eigen::Vector2d(u.dot(p), w.dot(p));
    s.b = Eigen::Vector2d(u.dot(q), w.dot(q));
    const double move_p = std::hypot(u.dot(dp), w.dot(dp));
    const double move_q = std::hypot(u.dot(dq), w.dot(dq));
    s.reach = std::max(move_p, move_q) + 0.5 * margin;
    s.lower_x = std::min(s.a.x(), s.b.x()) - s.reach;
    s.upper_x = std::max(s.a.x(), s.b.x()) + s.reach;
    s.lower_y = std::min(s.a.y(), s.b.y()) - s.reach;
    s.upper_y = std::max(s.a.y(), s.b.y()) + s.reach;
    segments.push_back(s);
  }
  // Sweep along x: only segments whose reach boxes overlap can come closer than their reaches.
  std::sort(segments.begin(), segments.end(),
            [](const Segment& a, const Segment& b) { return a.lower_x < b.lower_x; });
  for (size_t i = 0; i < segments.size(); ++i) {
    const Segment& s = segments[i];
    for (size_t j = i + 1; j < segments.size() && segments[j].lower_x <= s.upper_x; ++j) {
      const Segment& t = segments[j];
      if (t.lower_y > s.upper_y || s.lower_y > t.upper_y) continue;
      if (s.u == t.u || s.u == t.v || s.v == t.u || s.v == t.v) continue;  // neighbours on the loop
      if (segment_distance(s.a, s.b, t.a, t.b) <= s.reach + t.reach) return false;
    }
  }
  return true;
}

void culled_regions(const Bvh& bvh, const std::vector<char>& culled, std::vector<int>& region) {
  region.assign(bvh.num_triangles(), -1);
  // Preorder: the first culled node met on the way down is the topmost of its subtree, which
  // spans the nodes [node, node.next).
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const int num_nodes = static_cast<int>(nodes.size());
  int i = 0;
  while (i < num_nodes) {
    if (!culled[i]) {
      ++i;
      continue;
    }
    for (int k = i; k < nodes[i].next; ++k) {
      if (!nodes[k].is_leaf()) continue;
      for (int j = 0; j < nodes[k].count; ++j) region[bvh.triangle_order()[nodes[k].first + j]] = i;
    }
    i = nodes[i].next;
  }
}

}  // namespace weft
