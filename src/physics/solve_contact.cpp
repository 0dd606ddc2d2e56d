#include "physics/solve_contact.hpp"

#include <cmath>

#include "physics/sparse_hessian.hpp"

namespace weft {

bool ContactBlocks::assemble(SparseHessian& hessian, bool bound_off_pattern) {
  off_pattern.clear();
  for (size_t c = 0; c < blocks.size(); ++c) {
    const std::array<int, 4>& v = vertices[c];
    const std::array<double, 4>& w = weights[c];
    for (int j = 0; j < 4; ++j) {
      if (v[j] < 0) continue;
      hessian.add_vertex_block(v[j], (w[j] * w[j]) * blocks[c]);
      for (int k = j + 1; k < 4; ++k) {
        if (v[k] < 0) continue;
        if (hessian.add_block_pair(v[j], v[k], (w[j] * w[k]) * blocks[c])) continue;
        if (bound_off_pattern) {
          const Mat3 bound = std::abs(w[j] * w[k]) * blocks[c];
          hessian.add_vertex_block(v[j], bound);
          hessian.add_vertex_block(v[k], bound);
        } else {
          off_pattern.push_back({static_cast<int>(c), j, k});
        }
      }
    }
  }
  return !off_pattern.empty();
}

void ContactBlocks::add_coupling_product(const Eigen::VectorXd& free, const Eigen::VectorXd& p,
                                         Eigen::VectorXd& y) const {
  for (const std::array<int, 3>& entry : off_pattern) {
    const int c = entry[0];
    const int a = vertices[c][entry[1]], b = vertices[c][entry[2]];
    if (free[3 * a] == 0.0 || free[3 * b] == 0.0) continue;
    const double w = weights[c][entry[1]] * weights[c][entry[2]];
    y.segment<3>(3 * a) += w * (blocks[c] * p.segment<3>(3 * b));
    y.segment<3>(3 * b) += w * (blocks[c] * p.segment<3>(3 * a));
  }
}

}  // namespace weft
