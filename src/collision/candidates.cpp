#include "collision/candidates.hpp"

#include <algorithm>
#include <array>
#include <cstdint>

namespace weft {

namespace {

// Sorts 64-bit keys and drops repeats: least-significant-digit radix sort, a byte a pass, passes
// whose byte is the same in every key skipped (indices below 2^16 leave half the passes out).
// Linear in the keys where std::sort is n log n, which pays on the tens of thousands of pairs of a
// step.
void sort_unique_keys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  const size_t n = keys.size();
  scratch.resize(n);
  for (int shift = 0; shift < 64; shift += 8) {
    std::array<size_t, 257> start{};
    for (const std::uint64_t key : keys) ++start[((key >> shift) & 255u) + 1];
    if (std::find(start.begin() + 1, start.end(), n) != start.end()) continue;  // one digit for all
    for (int d = 0; d < 256; ++d) start[d + 1] += start[d];
    for (const std::uint64_t key : keys) scratch[start[(key >> shift) & 255u]++] = key;
    keys.swap(scratch);
  }
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

// Sorts pairs of non-negative indices by (first, second) and removes duplicates, through keys
// first << 32 | second.
template <typename T, int T::*First, int T::*Second>
void sort_and_deduplicate(std::vector<T>& items, std::vector<std::uint64_t>& keys,
                          std::vector<std::uint64_t>& scratch) {
  keys.resize(items.size());
  for (size_t k = 0; k < items.size(); ++k) {
    keys[k] = std::uint64_t(std::uint32_t(items[k].*First)) << 32 | std::uint32_t(items[k].*Second);
  }
  sort_unique_keys(keys, scratch);
  items.resize(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) {
    items[k].*First = static_cast<int>(keys[k] >> 32);
    items[k].*Second = static_cast<int>(keys[k] & 0xffffffffu);
  }
}

}  // namespace

MeshIndexOffsets next_offsets(const MeshIndexOffsets& offsets, int num_vertices, int num_triangles,
                              int num_edges) {
  return {offsets.vertex + num_vertices, offsets.triangle + num_triangles, offsets.edge + num_edges};
}

void sort_candidates(CollisionCandidates& candidates) {
  sort_and_deduplicate<VertexFacePair, &VertexFacePair::vertex, &VertexFacePair::triangle>(
      candidates.vertex_face, candidates.sort_keys, candidates.sort_scratch);
  sort_and_deduplicate<EdgeEdgePair, &EdgeEdgePair::edge_a, &EdgeEdgePair::edge_b>(
      candidates.edge_edge, candidates.sort_keys, candidates.sort_scratch);
}

namespace {

template <typename T>
void merge_new(std::vector<T>& all, std::vector<T>& added, std::vector<T>& scratch) {
  // Set difference in place (both sorted), then the two sorted runs merged through `scratch`.
  auto in_all = all.begin();
  auto kept = added.begin();
  for (auto it = added.begin(); it != added.end(); ++it) {
    in_all = std::lower_bound(in_all, all.end(), *it);
    if (in_all == all.end() || !(*in_all == *it)) *kept++ = *it;
  }
  added.erase(kept, added.end());
  if (added.empty()) return;
  scratch.resize(all.size() + added.size());
  std::merge(all.begin(), all.end(), added.begin(), added.end(), scratch.begin());
  all.swap(scratch);
}

}  // namespace

void merge_new_candidates(CollisionCandidates& all, CollisionCandidates& added) {
  merge_new(all.vertex_face, added.vertex_face, all.vertex_face_scratch);
  merge_new(all.edge_edge, added.edge_edge, all.edge_edge_scratch);
}

}  // namespace weft
