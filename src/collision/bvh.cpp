#include "collision/bvh.hpp"

#include <omp.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace weft {

double Aabb::surface_area() const {
  if (empty()) return 0.0;
  const Vec3 size = upper - lower;
  return 2.0 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x());
}

namespace {

// Below this many triangles, refitting the triangle boxes is not worth starting threads for.
constexpr int parallel_refit_threshold = 4096;

void check_positions(const Positions& x_start, const Positions& x_end, double margin, const char* where) {
  if (x_start.cols() != x_end.cols()) {
    throw std::invalid_argument(std::string(where) + ": x_start has " + std::to_string(x_start.cols()) +
                                " vertices but x_end has " + std::to_string(x_end.cols()));
  }
  if (!(margin >= 0.0)) {
    throw std::invalid_argument(std::string(where) + ": margin must be >= 0, got " + std::to_string(margin));
  }
}

}  // namespace

void Bvh::build(const Positions& x_start, const Positions& x_end, const Triangles& triangles, double margin,
                const BvhSettings& settings) {
  check_positions(x_start, x_end, margin, "Bvh::build");
  if (settings.max_leaf_size < 1 || settings.sah_bins < 2) {
    throw std::invalid_argument("Bvh::build: needs max_leaf_size >= 1 and sah_bins >= 2");
  }
  const int num_vertices = static_cast<int>(x_start.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (triangles(k, t) < 0 || triangles(k, t) >= num_vertices) {
        throw std::invalid_argument("Bvh::build: triangle " + std::to_string(t) + " has vertex index " +
                                    std::to_string(triangles(k, t)) + " outside [0, " +
                                    std::to_string(num_vertices) + ")");
      }
    }
  }
  settings_ = settings;
  triangles_ = triangles;
  num_vertices_ = num_vertices;
  triangle_boxes_.resize(triangles.cols());
  leaf_boxes_.resize(triangles.cols());
  compute_triangle_boxes(x_start, x_end, margin);
  build_nodes();
  refit_nodes();
  cost_at_build_ = cost_;
  ++builds_;
}

void Bvh::refit(const Positions& x_start, const Positions& x_end, double margin) {
  check_positions(x_start, x_end, margin, "Bvh::refit");
  if (x_start.cols() != num_vertices_) {
    throw std::invalid_argument("Bvh::refit: built for " + std::to_string(num_vertices_) + " vertices, got " +
                                std::to_string(x_start.cols()));
  }
  compute_triangle_boxes(x_start, x_end, margin);
  refit_nodes();
}

void Bvh::refit_moved(const Positions& x_start, const Positions& x_end, double margin,
                      const std::vector<char>& moved) {
  check_positions(x_start, x_end, margin, "Bvh::refit_moved");
  if (x_start.cols() != num_vertices_ || static_cast<int>(moved.size()) != num_vertices_) {
    throw std::invalid_argument("Bvh::refit_moved: built for " + std::to_string(num_vertices_) +
                                " vertices, got " + std::to_string(x_start.cols()) + " positions and " +
                                std::to_string(moved.size()) + " flags");
  }
  const int num_triangles = this->num_triangles();
  moved_entries_.resize(num_triangles);
  for (int t = 0; t < num_triangles; ++t) {
    moved_entries_[t] = moved[triangles_(0, t)] || moved[triangles_(1, t)] || moved[triangles_(2, t)];
    if (moved_entries_[t]) triangle_boxes_[t] = triangle_box(t, x_start, x_end, margin);
  }
  // Children come after their parent in preorder: a reverse sweep sees them first.
  const int num_nodes = static_cast<int>(nodes_.size());
  moved_nodes_.resize(num_nodes);
  for (int i = num_nodes - 1; i >= 0; --i) {
    const BvhNode& node = nodes_[i];
    bool below = false;
    if (node.is_leaf()) {
      for (int k = 0; k < node.count; ++k) below = below || moved_entries_[triangle_order_[node.first + k]];
    } else {
      below = moved_nodes_[i + 1] || moved_nodes_[node.right];
    }
    moved_nodes_[i] = below;
    if (below) refit_node(i);
  }
  sum_cost();
}

Aabb Bvh::triangle_box(int t, const Positions& x_start, const Positions& x_end, double margin) const {
  // The box over the triangle's three vertices at both ends of the step, then inflated.
  Aabb box;
  for (int k = 0; k < 3; ++k) {
    const int v = triangles_(k, t);
    box.grow(Vec3(x_start.col(v)));
    box.grow(Vec3(x_end.col(v)));
  }
  box.lower.array() -= margin;
  box.upper.array() += margin;
  return box;
}

void Bvh::compute_triangle_boxes(const Positions& x_start, const Positions& x_end, double margin) {
  const int num_triangles = this->num_triangles();
#pragma omp parallel for schedule(static) if (num_triangles > parallel_refit_threshold)
  for (int t = 0; t < num_triangles; ++t) triangle_boxes_[t] = triangle_box(t, x_start, x_end, margin);
}

void Bvh::build_nodes() {
  const int num_triangles = this->num_triangles();
  nodes_.clear();
  triangle_order_.resize(num_triangles);
  std::iota(triangle_order_.begin(), triangle_order_.end(), 0);
  if (num_triangles == 0) return;
  nodes_.reserve(2 * static_cast<std::size_t>(num_triangles));

  std::vector<Vec3>& centroids = centroids_;
  centroids.resize(num_triangles);
  for (int t = 0; t < num_triangles; ++t)
    centroids[t] = 0.5 * (triangle_boxes_[t].lower + triangle_boxes_[t].upper);

  const int num_bins = settings_.sah_bins;
  std::vector<Aabb>& bin_boxes = bin_boxes_;
  std::vector<int>& bin_counts = bin_counts_;
  std::vector<double>& right_areas = right_areas_;
  bin_boxes.resize(num_bins);
  bin_counts.resize(num_bins);
  right_areas.resize(num_bins);

  // Top-down with an explicit stack of triangle ranges. The left child is pushed last so it is
  // created right after its parent (preorder); a right child tells its parent where it landed.
  // The stack grows by at most one range per level, and there are at most num_triangles levels.
  std::vector<BuildRange>& ranges = ranges_;
  ranges.reserve(static_cast<std::size_t>(num_triangles) + 1);
  ranges.assign(1, BuildRange{0, num_triangles, -1});
  while (!ranges.empty()) {
    const BuildRange range = ranges.back();
    ranges.pop_back();
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    if (range.parent_of_right >= 0) nodes_[range.parent_of_right].right = index;
    const int count = range.end - range.begin;
    if (count <= settings_.max_leaf_size) {
      nodes_[index].first = range.begin;
      nodes_[index].count = count;
      continue;
    }

    // Split along the longest axis of the centroids' bounds.
    Aabb centroid_bounds;
    for (int i = range.begin; i < range.end; ++i) centroid_bounds.grow(centroids[triangle_order_[i]]);
    int axis = 0;
    (centroid_bounds.upper - centroid_bounds.lower).maxCoeff(&axis);
    const double low = centroid_bounds.lower[axis];
    const double extent = centroid_bounds.upper[axis] - low;
    int middle = range.begin + count / 2;
    if (extent > 0.0) {
      // Binned surface area heuristic: bin the centroids, then pick the plane between bins
      // that minimises area(left) * count(left) + area(right) * count(right).
      const auto bin_of = [&](int t) {
        const int bin = static_cast<int>(num_bins * ((centroids[t][axis] - low) / extent));
        return std::min(std::max(bin, 0), num_bins - 1);
      };
      std::fill(bin_boxes.begin(), bin_boxes.end(), Aabb());
      std::fill(bin_counts.begin(), bin_counts.end(), 0);
      for (int i = range.begin; i < range.end; ++i) {
        const int t = triangle_order_[i];
        const int bin = bin_of(t);
        bin_boxes[bin].grow(triangle_boxes_[t]);
        ++bin_counts[bin];
      }
      Aabb right_box;
      for (int b = num_bins - 1; b > 0; --b) {
        right_box.grow(bin_boxes[b]);
        right_areas[b] = right_box.surface_area();
      }
      Aabb left_box;
      int left_count = 0;
      int best_bin = 0;
      double best_cost = std::numeric_limits<double>::infinity();
      for (int b = 0; b + 1 < num_bins; ++b) {
        left_box.grow(bin_boxes[b]);
        left_count += bin_counts[b];
        const double cost = left_box.surface_area() * left_count + right_areas[b + 1] * (count - left_count);
        if (cost < best_cost) {
          best_cost = cost;
          best_bin = b;
        }
      }
      // Bin 0 and the last bin both hold a centroid, so both sides are non-empty.
      const auto split =
          std::partition(triangle_order_.begin() + range.begin, triangle_order_.begin() + range.end,
                         [&](int t) { return bin_of(t) <= best_bin; });
      middle = static_cast<int>(split - triangle_order_.begin());
    }
    ranges.push_back({middle, range.end, index});
    ranges.push_back({range.begin, middle, -1});
  }

  // Escape indices, children first: a leaf is followed by the next node, an inner node's
  // subtree ends where its right child's does.
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    BvhNode& node = nodes_[i];
    node.next = node.is_leaf() ? i + 1 : nodes_[node.right].next;
  }
}

void Bvh::refit_node(int i) {
  BvhNode& node = nodes_[i];
  Aabb box;
  if (node.is_leaf()) {
    for (int k = 0; k < node.count; ++k) {
      const Aabb& leaf_box = triangle_boxes_[triangle_order_[node.first + k]];
      leaf_boxes_[node.first + k] = leaf_box;
      box.grow(leaf_box);
    }
  } else {
    box = nodes_[i + 1].box;
    box.grow(nodes_[node.right].box);
  }
  node.box = box;
  node_areas_[i] = box.surface_area();
}

void Bvh::refit_nodes() {
  // Children come after their parent in preorder, so a reverse sweep sees them first. Subtrees
  // of at most `small` nodes are swept in parallel, then the nodes above them; the areas are
  // summed afterwards in the reverse order of the serial sweep, so the cost is the same bits.
  const int num_nodes = static_cast<int>(nodes_.size());
  node_areas_.resize(num_nodes);
  const int small = std::max(64, num_nodes / 64);
  subtrees_.clear();
  upper_nodes_.clear();
  for (int k = 0; k < num_nodes;) {
    if (nodes_[k].next - k <= small) {
      subtrees_.push_back(k);
      k = nodes_[k].next;
    } else {
      upper_nodes_.push_back(k);
      ++k;
    }
  }
  const int num_subtrees = static_cast<int>(subtrees_.size());
#pragma omp parallel for schedule(dynamic, 1) if (num_nodes > parallel_refit_threshold && num_subtrees > 1)
  for (int j = 0; j < num_subtrees; ++j) {
    for (int i = nodes_[subtrees_[j]].next - 1; i >= subtrees_[j]; --i) refit_node(i);
  }
  for (auto k = upper_nodes_.rbegin(); k != upper_nodes_.rend(); ++k) refit_node(*k);
  sum_cost();
}

void Bvh::sum_cost() {
  const int num_nodes = static_cast<int>(nodes_.size());
  double total_area = 0.0;
  for (int i = num_nodes - 1; i >= 0; --i) total_area += node_areas_[i];
  const double root_area = nodes_.empty() ? 0.0 : nodes_[0].box.surface_area();
  cost_ = root_area > 0.0 ? total_area / root_area : 1.0;
}

void find_triangles_in_box(const Bvh& bvh, const Aabb& box, std::vector<int>& triangles) {
  // Stackless walk of the preorder array: enter a node whose box overlaps, else skip its subtree.
  triangles.clear();
  const std::vector<BvhNode>& nodes = bvh.nodes();
  const int num_nodes = static_cast<int>(nodes.size());
  int i = 0;
  while (i < num_nodes) {
    const BvhNode& node = nodes[i];
    if (!node.box.overlaps(box)) {
      i = node.next;
      continue;
    }
    if (node.is_leaf()) {
      for (int k = 0; k < node.count; ++k) {
        const int t = bvh.triangle_order()[node.first + k];
        if (bvh.triangle_boxes()[t].overlaps(box)) triangles.push_back(t);
      }
    }
    ++i;
  }
  std::sort(triangles.begin(), triangles.end());
}

}  // namespace weft
