#include "physics/solve_contact.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

bool ContactBlocks::index_coupled() {
  coupled.clear();
  for (size_t c = 0; c < vertices.size(); ++c) {
    int inside = 0;
    for (int k = 0; k < 4; ++k) inside += vertices[c][k] >= 0 ? 1 : 0;
    if (inside > 1) coupled.push_back(static_cast<int>(c));
  }
  return !coupled.empty();
}

void ContactBlocks::add_diagonal(SparseHessian& hessian) const {
  for (size_t c = 0; c < blocks.size(); ++c) {
    for (int k = 0; k < 4; ++k) {
      const int v = vertices[c][k];
      if (v >= 0) hessian.add_vertex_block(v, (weights[c][k] * weights[c][k]) * blocks[c]);
    }
  }
}

void ContactBlocks::add_coupling_product(const Eigen::VectorXd& free, const Eigen::VectorXd& p,
                                         Eigen::VectorXd& y) const {
  for (const int c : coupled) {
    const std::array<int, 4>& v = vertices[c];
    const std::array<double, 4>& w = weights[c];
    // K (sum over the contact's free vertices k of w_k p_k), then each free vertex j takes
    // w_j times it less its own term.
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      if (v[k] >= 0 && free[3 * v[k]] != 0.0) sum += w[k] * p.segment<3>(3 * v[k]);
    }
    for (int j = 0; j < 4; ++j) {
      if (v[j] < 0 || free[3 * v[j]] == 0.0) continue;
      const Vec3 others = sum - w[j] * p.segment<3>(3 * v[j]);
      y.segment<3>(3 * v[j]) += w[j] * (blocks[c] * others);
    }
  }
}

}  // namespace weft
