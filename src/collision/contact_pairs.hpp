#pragma once
// Candidate primitive pairs handed from a broad phase to the narrow phase. Indices refer to one
// combined index space: triangles (3 x n_triangles) and edges (2 x n_edges) over all vertices.

#include <cstddef>
#include <vector>

namespace weft {

struct VertexFacePair {
  int vertex;    // combined vertex index
  int triangle;  // combined triangle index; the vertex is not one of its corners

  bool operator==(const VertexFacePair& other) const {
    return vertex == other.vertex && triangle == other.triangle;
  }
  bool operator<(const VertexFacePair& other) const {
    return vertex != other.vertex ? vertex < other.vertex : triangle < other.triangle;
  }
};

struct EdgeEdgePair {
  int edge_a;  // combined edge indices, edge_a < edge_b; the edges share no vertex
  int edge_b;

  bool operator==(const EdgeEdgePair& other) const {
    return edge_a == other.edge_a && edge_b == other.edge_b;
  }
  bool operator<(const EdgeEdgePair& other) const {
    return edge_a != other.edge_a ? edge_a < other.edge_a : edge_b < other.edge_b;
  }
};

// A run of pairs inside a larger array (C++17 has no std::span); a vector converts to one.
template <typename Pair>
struct PairRange {
  const Pair* first = nullptr;
  const Pair* last = nullptr;

  PairRange(const Pair* begin, const Pair* end) : first(begin), last(end) {}
  PairRange(const std::vector<Pair>& pairs) : first(pairs.data()), last(pairs.data() + pairs.size()) {}  // NOLINT
  const Pair* begin() const { return first; }
  const Pair* end() const { return last; }
  std::size_t size() const { return static_cast<std::size_t>(last - first); }
  bool empty() const { return first == last; }
};

// Pairs sorted into numbered groups in one array, group g at [start[g], start[g + 1]): filled by
// counting (count, then place), so it allocates only when the total outgrows every earlier one.
template <typename Pair>
struct GroupedPairs {
  std::vector<Pair> pairs;
  std::vector<int> start;  // (n_groups + 1)

  // Empties every group and sizes the counts; then count() each pair, place_counted(), and
  // place() the same pairs in any order.
  void begin_counting(int num_groups) { start.assign(num_groups + 2, 0); }
  void count(int group) { ++start[group + 2]; }
  void place_counted() {
    for (std::size_t g = 2; g < start.size(); ++g) start[g] += start[g - 1];
    pairs.resize(start.back());
  }
  void place(int group, const Pair& pair) { pairs[start[group + 1]++] = pair; }
  int num_groups() const { return static_cast<int>(start.size()) - 2; }
  PairRange<Pair> group(int g) const { return {pairs.data() + start[g], pairs.data() + start[g + 1]}; }
};

}  // namespace weft
