#pragma once
// Parallel evaluation of element terms (membrane triangles, bending hinges). The elements are cut
// into patches of consecutive indices (neighbours in a grid or a loaded mesh are mostly close in
// index, so a patch touches a compact piece of the vectors and the Hessian), and the patches are
// coloured such that no two patches of one colour share a vertex. The colours run one after
// another and the patches of a colour in parallel, each patch's elements in order, so every
// write of an element (its gradient columns, its Hessian blocks) touches vertices no other
// thread touches at that time: no locks, no atomics. Every vertex receives its contributions in
// the same order whatever the thread count, and the energy is summed patch by patch in patch
// order, so a run is bit-identical at 1 and at 2 threads.
#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace weft {

class ElementColoring {
 public:
  ElementColoring() = default;

  // Greedy colouring of the patches of `elements` (K vertex indices per column, all in
  // [0, num_vertices)).
  template <int K>
  ElementColoring(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements, int num_vertices);

  int num_colors() const { return static_cast<int>(color_starts_.size()) - 1; }
  int patch_of(int element) const { return element / patch_size; }
  int color_of_patch(int patch) const { return patch_color_[patch]; }

  // Calls energy_of(e) for every element e in [0, count) (each exactly once) and returns the sum
  // of what it returns. Without a colouring of `count` elements (a term built without one) the
  // elements run in order on this thread. Not reentrant: one evaluation of a term at a time.
  template <typename EnergyOf>
  double sum_over_elements(int count, EnergyOf&& energy_of) const;

 private:
  static constexpr int patch_size = 64;
  int num_elements_ = 0;
  std::vector<int> patch_color_;   // per patch
  std::vector<int> patches_;       // patch indices, colour by colour
  std::vector<int> color_starts_;  // colour c is patches_[color_starts_[c] .. color_starts_[c + 1])
  mutable std::vector<double> patch_energy_;  // per patch, summed in patch order
};

template <int K>
ElementColoring::ElementColoring(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements, int num_vertices)
    : num_elements_(static_cast<int>(elements.cols())) {
  const int num_patches = (num_elements_ + patch_size - 1) / patch_size;
  // Colour of each patch: the smallest colour none of its vertices has been given yet, with a
  // vertex's colours kept as a 64-bit mask. A patch that finds all 64 taken gets a colour of its
  // own past the mask (it then runs alone, which is still correct).
  std::vector<unsigned long long> used(num_vertices, 0ull);
  patch_color_.resize(num_patches);
  int colors = 0;
  int overflow_color = 64;
  for (int p = 0; p < num_patches; ++p) {
    const int end = std::min(num_elements_, (p + 1) * patch_size);
    unsigned long long taken = 0ull;
    for (int e = p * patch_size; e < end; ++e) {
      for (int k = 0; k < K; ++k) taken |= used[elements(k, e)];
    }
    int c = 0;
    while (c < 64 && (taken >> c & 1ull)) ++c;
    if (c == 64) {
      c = overflow_color++;
    } else {
      for (int e = p * patch_size; e < end; ++e) {
        for (int k = 0; k < K; ++k) used[elements(k, e)] |= 1ull << c;
      }
    }
    patch_color_[p] = c;
    colors = std::max(colors, c + 1);
  }
  color_starts_.assign(colors + 1, 0);
  for (int p = 0; p < num_patches; ++p) ++color_starts_[patch_color_[p] + 1];
  for (int c = 0; c < colors; ++c) color_starts_[c + 1] += color_starts_[c];
  patches_.resize(num_patches);
  std::vector<int> next(color_starts_.begin(), color_starts_.end() - 1);
  for (int p = 0; p < num_patches; ++p) patches_[next[patch_color_[p]]++] = p;
  patch_energy_.assign(num_patches, 0.0);
}

template <typename EnergyOf>
double ElementColoring::sum_over_elements(int count, EnergyOf&& energy_of) const {
  if (count != num_elements_ || count == 0) {
    double energy = 0.0;
    for (int e = 0; e < count; ++e) energy += energy_of(e);
    return energy;
  }
  // One parallel region, a barrier between colours (not a region each).
#pragma omp parallel
  for (int c = 0; c < num_colors(); ++c) {
    const int begin = color_starts_[c];
    const int size = color_starts_[c + 1] - begin;
#pragma omp for schedule(static)
    for (int j = 0; j < size; ++j) {
      const int p = patches_[begin + j];
      const int end = std::min(count, (p + 1) * patch_size);
      double sum = 0.0;
      for (int e = p * patch_size; e < end; ++e) sum += energy_of(e);
      patch_energy_[p] = sum;
    }
  }
  double energy = 0.0;
  for (const double sum : patch_energy_) energy += sum;
  return energy;
}

}  // namespace weft
