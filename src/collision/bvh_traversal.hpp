#pragma once
// The walk behind every pair query over two hierarchies (or one against itself): node pairs
// whose boxes overlap are split until both are leaves, and each pair of leaf entries whose
// boxes overlap is handed to a visitor. A template, so that the primitive-level broad phase
// (primitive_queries.cpp) and untangling's edge-triangle search (untangling.cpp) each filter
// pairs where they are found, with no call through a pointer per pair and no intermediate list.
//
// The root task is split breadth first, serially, into a fixed number of node-pair tasks (the
// same split on any thread count), which threads then take dynamically. Which thread visits a
// pair therefore varies from run to run: a visitor writes into per-thread buffers and the
// caller must make its result independent of that order (a sort).
#include <omp.h>

#include <algorithm>
#include <vector>

#include "collision/bvh.hpp"

namespace weft {
namespace bvh_traversal {

// Node-pair tasks handed to threads: enough that dynamic scheduling balances two to a few dozen
// threads; a fixed number, so the split of the work is the same for any thread count.
constexpr int target_task_count = 256;

// Splits the node pair `task` one level into `out`. Returns false when it cannot be split
// (within one leaf, or two leaves): the caller keeps it whole. A pair of disjoint nodes splits
// into nothing. With `self`, (n, n) stands for the pairs within node n, which are its two
// children's within-pairs and the pair of its children; a node flagged in `culled` has none.
template <bool self>
bool split_task(const Bvh& first_bvh, const Bvh& second_bvh, TrianglePair task, const char* culled,
                std::vector<TrianglePair>& out) {
  const BvhNode& a = first_bvh.nodes()[task.a];
  const BvhNode& b = second_bvh.nodes()[task.b];
  if (self && task.a == task.b) {
    if (culled != nullptr && culled[task.a]) return true;
    if (a.is_leaf()) return false;
    out.push_back({task.a + 1, task.a + 1});
    out.push_back({a.right, a.right});
    out.push_back({task.a + 1, a.right});
    return true;
  }
  if (!a.box.overlaps(b.box)) return true;
  if (a.is_leaf() && b.is_leaf()) return false;
  // Descend the larger box, so both sides shrink at a similar pace.
  if (b.is_leaf() || (!a.is_leaf() && first_bvh.node_areas()[task.a] >= second_bvh.node_areas()[task.b])) {
    out.push_back({task.a + 1, task.b});
    out.push_back({a.right, task.b});
  } else {
    out.push_back({task.a, task.b + 1});
    out.push_back({task.a, b.right});
  }
  return true;
}

// Entries of leaf `a` of `first` against leaf `b` of `second` whose boxes overlap, handed to
// visit(thread, s, t) with s of `first` and t of `second`. With `self`, (a, a) means the pairs
// within the leaf, each visited once (s before t in leaf order, not by index).
template <bool self, typename Visit>
void visit_leaf_pairs(const Bvh& first, const Bvh& second, int a, int b, int thread, Visit& visit) {
  const BvhNode& leaf_a = first.nodes()[a];
  const BvhNode& leaf_b = second.nodes()[b];
  const std::vector<int>& order_a = first.triangle_order();
  const std::vector<int>& order_b = second.triangle_order();
  const Aabb* boxes_a = first.leaf_boxes().data() + leaf_a.first;
  const Aabb* boxes_b = second.leaf_boxes().data() + leaf_b.first;
  for (int i = 0; i < leaf_a.count; ++i) {
    const Aabb& box_s = boxes_a[i];
    for (int j = (self && a == b) ? i + 1 : 0; j < leaf_b.count; ++j) {
      if (box_s.overlaps(boxes_b[j])) visit(thread, order_a[leaf_a.first + i], order_b[leaf_b.first + j]);
    }
  }
}

// Visits every pair of entries whose boxes overlap: of `first` against `second`, or with `self`
// (second is first) every unordered pair of distinct entries once, except those within a node
// flagged in `culled`; with `self` and `within`, only the pairs within the listed nodes (none
// nested in another). Runs on `num_threads` OpenMP threads (visit's `thread` is below it, so
// the caller sizes its per-thread buffers by it); `buffers` holds the tasks and the per-thread
// stacks, which grow once and are then reused.
template <bool self, typename Visit>
void visit_overlapping_pairs(const Bvh& first, const Bvh& second, const char* culled,
                             BvhQueryBuffers& buffers, int num_threads, Visit& visit,
                             const std::vector<int>* within = nullptr) {
  if (first.nodes().empty() || second.nodes().empty()) return;

  // Tasks: split every splittable task per round; unsplittable ones carry over unchanged.
  std::vector<TrianglePair>& tasks = buffers.tasks;
  tasks.clear();
  if (self && within != nullptr) {
    for (const int node : *within) tasks.push_back({node, node});
    if (tasks.empty()) return;
  } else {
    tasks.push_back({0, 0});
  }
  while (static_cast<int>(tasks.size()) < target_task_count) {
    std::vector<TrianglePair>& next = buffers.next_tasks;
    next.clear();
    bool split_any = false;
    for (const TrianglePair& task : tasks) {
      if (split_task<self>(first, second, task, culled, next)) {
        split_any = true;
      } else {
        next.push_back(task);
      }
    }
    tasks.swap(next);
    if (!split_any) break;
  }
  if (static_cast<int>(buffers.thread_stacks.size()) < num_threads) buffers.thread_stacks.resize(num_threads);

  // Traversal: dynamic scheduling, since subtrees differ widely in how many pairs they hold.
  const int num_tasks = static_cast<int>(tasks.size());
#pragma omp parallel num_threads(num_threads)
  {
    const int thread = omp_get_thread_num();
    std::vector<TrianglePair>& stack = buffers.thread_stacks[thread];
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < num_tasks; ++k) {
      stack.clear();
      stack.push_back(tasks[k]);
      while (!stack.empty()) {
        const TrianglePair top = stack.back();
        stack.pop_back();
        if (!split_task<self>(first, second, top, culled, stack)) {
          visit_leaf_pairs<self>(first, second, top.a, top.b, thread, visit);
        }
      }
    }
  }
}

}  // namespace bvh_traversal
}  // namespace weft
