#include "physics/contact_penalty.hpp"

#include "physics/sparse_hessian.hpp"

namespace weft {

namespace {

// delta - g(x): positive while the contact is closer than its thickness.
double overlap(const PenaltyContact& contact, const Positions& x) {
  double gap = contact.offset;
  for (int k = 0; k < 4; ++k) {
    if (contact.vertices[k] >= 0) gap += contact.weights[k] * contact.normal.dot(x.col(contact.vertices[k]));
  }
  return contact.thickness - gap;
}

}  // namespace

double ContactPenalty::evaluate(const Positions& x, Positions* gradient, SparseHessian* hessian) const {
  if (!active()) return 0.0;
  double energy = 0.0;
  for (const PenaltyContact& contact : contacts) {
    const double d = overlap(contact, x);
    if (!(d > 0.0)) continue;
    energy += 0.5 * stiffness * d * d;
    const Mat3 normal_block = stiffness * contact.normal * contact.normal.transpose();
    for (int k = 0; k < 4; ++k) {
      const int v = contact.vertices[k];
      if (v < 0) continue;
      const double w = contact.weights[k];
      if (gradient != nullptr) gradient->col(v) -= (stiffness * d * w) * contact.normal;
      if (hessian != nullptr) hessian->add_vertex_block(v, (w * w) * normal_block);
    }
  }
  return energy;
}

void ContactPenalty::add_coupling_product(const Positions& x, const Eigen::VectorXd& free,
                                          const Eigen::VectorXd& p, Eigen::VectorXd& y) const {
  if (!active()) return;
  for (const PenaltyContact& contact : contacts) {
    if (!(overlap(contact, x) > 0.0)) continue;
    // Normal components of p at the contact's free vertices.
    std::array<double, 4> normal_p{};
    for (int k = 0; k < 4; ++k) {
      const int v = contact.vertices[k];
      if (v >= 0 && free[3 * v] != 0.0) normal_p[k] = contact.normal.dot(p.segment<3>(3 * v));
    }
    for (int j = 0; j < 4; ++j) {
      const int v = contact.vertices[j];
      if (v < 0 || free[3 * v] == 0.0) continue;
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) {
        if (k != j && contact.vertices[k] != v) sum += contact.weights[k] * normal_p[k];
      }
      y.segment<3>(3 * v) += (stiffness * contact.weights[j] * sum) * contact.normal;
    }
  }
}

}  // namespace weft
