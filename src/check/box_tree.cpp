#include "check/box_tree.hpp"

#include <algorithm>
#include <numeric>

namespace weft {

namespace {

constexpr int leaf_size = 4;

struct Node {
  Vec3 lower;
  Vec3 upper;
  int first = 0;  // the node's boxes are order[first, first + count)
  int count = 0;
  int left = -1;  // children, or -1 for a leaf
  int right = -1;
  bool all_obstacles = false;
};

bool overlap(const Vec3& a_lower, const Vec3& a_upper, const Vec3& b_lower, const Vec3& b_upper) {
  return !((a_upper.array() < b_lower.array()).any() || (b_upper.array() < a_lower.array()).any());
}

class BoxTree {
 public:
  explicit BoxTree(const std::vector<CheckBox>& boxes) : boxes_(boxes), order_(boxes.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    nodes_.reserve(2 * boxes.size() / leaf_size + 1);
    if (!boxes.empty()) build(0, static_cast<int>(boxes.size()));
  }

  std::vector<std::pair<int, int>> pairs() {
    found_.reserve(8 * boxes_.size());  // a mesh's triangle touches about a dozen neighbours' boxes
    if (!nodes_.empty()) self_pairs(0);
    return std::move(found_);
  }

 private:
  // The node over order_[first, first + count): bounds, then a split at the median centre along
  // the widest axis of the centres.
  int build(int first, int count) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Node node;
    node.first = first;
    node.count = count;
    node.lower = boxes_[order_[first]].lower;
    node.upper = boxes_[order_[first]].upper;
    node.all_obstacles = true;
    Vec3 centre_lower = boxes_[order_[first]].lower + boxes_[order_[first]].upper;
    Vec3 centre_upper = centre_lower;
    for (int i = first; i < first + count; ++i) {
      const CheckBox& box = boxes_[order_[i]];
      node.lower = node.lower.cwiseMin(box.lower);
      node.upper = node.upper.cwiseMax(box.upper);
      node.all_obstacles = node.all_obstacles && box.obstacle;
      centre_lower = centre_lower.cwiseMin(box.lower + box.upper);
      centre_upper = centre_upper.cwiseMax(box.lower + box.upper);
    }
    if (count > leaf_size) {
      int axis = 0;
      (centre_upper - centre_lower).maxCoeff(&axis);
      const int half = count / 2;
      std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                       [&](int a, int b) {
                         return boxes_[a].lower[axis] + boxes_[a].upper[axis] <
                                boxes_[b].lower[axis] + boxes_[b].upper[axis];
                       });
      node.left = build(first, half);
      node.right = build(first + half, count - half);
    }
    nodes_[index] = node;
    return index;
  }

  void leaf_pairs(const Node& a, const Node& b) {
    for (int i = a.first; i < a.first + a.count; ++i) {
      for (int j = b.first; j < b.first + b.count; ++j) add_if_overlapping(order_[i], order_[j]);
    }
  }

  void add_if_overlapping(int i, int j) {
    const CheckBox& x = boxes_[i];
    const CheckBox& y = boxes_[j];
    if ((x.obstacle && y.obstacle) || !overlap(x.lower, x.upper, y.lower, y.upper)) return;
    found_.emplace_back(std::min(i, j), std::max(i, j));
  }

  // Pairs within one node's boxes.
  void self_pairs(int index) {
    const Node& node = nodes_[index];
    if (node.all_obstacles) return;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        for (int j = i + 1; j < node.first + node.count; ++j) add_if_overlapping(order_[i], order_[j]);
      }
      return;
    }
    self_pairs(node.left);
    self_pairs(node.right);
    cross_pairs(node.left, node.right);
  }

  // Pairs with one box under node a and the other under node b (disjoint nodes).
  void cross_pairs(int a, int b) {
    const Node& x = nodes_[a];
    const Node& y = nodes_[b];
    if ((x.all_obstacles && y.all_obstacles) || !overlap(x.lower, x.upper, y.lower, y.upper)) return;
    if (x.left < 0 && y.left < 0) {
      leaf_pairs(x, y);
    } else if (y.left < 0 || (x.left >= 0 && x.count >= y.count)) {
      cross_pairs(x.left, b);
      cross_pairs(x.right, b);
    } else {
      cross_pairs(a, y.left);
      cross_pairs(a, y.right);
    }
  }

  const std::vector<CheckBox>& boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  std::vector<std::pair<int, int>> found_;
};

}  // namespace

std::vector<std::pair<int, int>> overlapping_box_pairs(const std::vector<CheckBox>& boxes) {
  return BoxTree(boxes).pairs();
}

}  // namespace weft
