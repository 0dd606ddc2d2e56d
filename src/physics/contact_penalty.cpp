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

// The cloth vertex of a contact holding exactly one, else -1.
int single_vertex(const PenaltyContact& contact) {
  int vertex = -1;
  for (int k = 0; k < 4; ++k) {
    const int v = contact.vertices[k];
    if (v < 0 || v == vertex) continue;
    if (vertex >= 0) return -1;
    vertex = v;
  }
  return vertex;
}

}  // namespace

void ContactPenalty::index_vertices(int num_vertices) {
  coupled_ = false;
  vertex_start_.assign(num_vertices + 1, 0);
  for (const PenaltyContact& contact : contacts) {
    const int v = single_vertex(contact);
    if (v < 0) {
      coupled_ = true;
    } else {
      ++vertex_start_[v + 1];
    }
  }
  for (int v = 0; v < num_vertices; ++v) vertex_start_[v + 1] += vertex_start_[v];
  vertex_contacts_.resize(vertex_start_[num_vertices]);
  for (int c = 0, size = static_cast<int>(contacts.size()); c < size; ++c) {
    const int v = single_vertex(contacts[c]);
    if (v >= 0) vertex_contacts_[vertex_start_[v]++] = c;
  }
  for (int v = num_vertices; v > 0; --v) vertex_start_[v] = vertex_start_[v - 1];
  vertex_start_[0] = 0;
  indexed_ = contacts.size();
}

double ContactPenalty::vertex_energy(int v, const Positions& x, Vec3* gradient, Mat3* hessian) const {
  if (v + 1 >= static_cast<int>(vertex_start_.size())) return 0.0;
  double energy = 0.0;
  for (int k = vertex_start_[v]; k < vertex_start_[v + 1]; ++k) {
    const PenaltyContact& contact = contacts[vertex_contacts_[k]];
    const double d = overlap(contact, x);
    if (!(d > 0.0)) continue;
    double w = 0.0;  // the vertex's weight (summed if it fills two corners)
    for (int j = 0; j < 4; ++j) w += contact.vertices[j] == v ? contact.weights[j] : 0.0;
    energy += 0.5 * contact.stiffness * d * d;
    if (gradient != nullptr) *gradient -= (contact.stiffness * d * w) * contact.normal;
    if (hessian != nullptr) *hessian += (contact.stiffness * w * w) * contact.normal * contact.normal.transpose();
  }
  return energy;
}

double ContactPenalty::evaluate(const Positions& x, Positions* gradient, SparseHessian* hessian) const {
  if (!active()) return 0.0;
  double energy = 0.0;
  for (const PenaltyContact& contact : contacts) {
    const double d = overlap(contact, x);
    if (!(d > 0.0)) continue;
    const double stiffness = contact.stiffness;
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
      y.segment<3>(3 * v) += (contact.stiffness * contact.weights[j] * sum) * contact.normal;
    }
  }
}

}  // namespace weft
