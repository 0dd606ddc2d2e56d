#include "physics/newton_tail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/topology.hpp"
#include "physics/bending.hpp"

namespace weft {

namespace {

// A tail step raising the largest residual by more than this is undone (a collapsing wing).
constexpr double diverging_factor = 100.0;

template <int K>
int corner_of(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements, int e, int vertex) {
  for (int k = 0; k < K; ++k) {
    if (elements(k, e) == vertex) return k;
  }
  return -1;
}

}  // namespace

bool NewtonTail::supports(const ClothModel& model) {
  return model.springs.size() == 0 && !model.air_drag.enabled() && !model.pressure.enabled;
}

void NewtonTail::prepare(const ClothModel& model) {
  const int n = static_cast<int>(model.rest_positions.cols());
  num_vertices_ = n;
  const Triangles empty_triangles(3, 0);
  const Eigen::Matrix4Xi empty_hinges(4, 0);
  vertex_incidence<3>(model.membrane.enabled() ? model.triangles : empty_triangles, n, triangle_starts_,
                      triangle_list_);
  vertex_incidence<4>(model.bending.enabled() ? model.bending.hinges : empty_hinges, n, hinge_starts_,
                      hinge_list_);
  std::vector<std::vector<int>> neighbours(n);
  for (int i = 0; i < n; ++i) {
    for (int k = triangle_starts_[i]; k < triangle_starts_[i + 1]; ++k) {
      for (int c = 0; c < 3; ++c) neighbours[i].push_back(model.triangles(c, triangle_list_[k]));
    }
    for (int k = hinge_starts_[i]; k < hinge_starts_[i + 1]; ++k) {
      for (int c = 0; c < 4; ++c) neighbours[i].push_back(model.bending.hinges(c, hinge_list_[k]));
    }
  }
  neighbour_starts_.assign(n + 1, 0);
  neighbour_list_.clear();
  for (int i = 0; i < n; ++i) {
    std::vector<int>& list = neighbours[i];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    neighbour_list_.insert(neighbour_list_.end(), list.begin(), list.end());
    neighbour_starts_[i + 1] = static_cast<int>(neighbour_list_.size());
  }
  region_.clear();
  region_.reserve(n);
  touched_.clear();
  touched_.reserve(n);
  local_.assign(n, -1);
  touched_mark_.assign(n, 0);
  region_triangles_.clear();
  region_triangles_.reserve(model.triangles.cols());
  triangle_mark_.assign(model.triangles.cols(), 0);
  region_hinges_.clear();
  region_hinges_.reserve(model.bending.hinges.cols());
  hinge_mark_.assign(model.bending.hinges.cols(), 0);
  for (Eigen::VectorXd* v : {&region_gradient_, &dx_, &r_, &z_, &p_, &q_}) v->setZero(3 * n);
  inverse_blocks_.assign(n, Mat3::Identity());
  saved_.setZero(3, n);
  step_.setZero(3, n);
  partial_gradient_.setZero(3, n);
  new_partial_gradient_.setZero(3, n);
  moving_.assign(n, 0);
}

int NewtonTail::collect_region(const ClothModel& model, double h, double tolerance, double largest,
                               const Positions& gradient) {
  const auto is_above = [&](int i) { return h * gradient.col(i).norm() * model.inverse_mass[i] > tolerance; };
  // Counted first: most calls (early global iterations) find too many to go on.
  int above = 0;
  for (int i = 0; i < num_vertices_; ++i) above += is_above(i) ? 1 : 0;
  if (above == 0 || above > largest) return above;

  for (const int v : region_) {
    local_[v] = -1;
    moving_[v] = 0;
  }
  for (const int v : touched_) touched_mark_[v] = 0;
  for (const int t : region_triangles_) triangle_mark_[t] = 0;
  for (const int e : region_hinges_) hinge_mark_[e] = 0;
  region_.clear();
  touched_.clear();
  region_triangles_.clear();
  region_hinges_.clear();
  const auto add = [&](int v) {
    if (local_[v] < 0 && model.inverse_mass[v] > 0.0) {
      local_[v] = static_cast<int>(region_.size());
      moving_[v] = 1;
      region_.push_back(v);
    }
  };
  for (int i = 0; i < num_vertices_; ++i) {
    if (!is_above(i)) continue;
    add(i);
    for (int k = neighbour_starts_[i]; k < neighbour_starts_[i + 1]; ++k) add(neighbour_list_[k]);
  }
  const auto touch = [&](int v) {
    if (!touched_mark_[v]) {
      touched_mark_[v] = 1;
      touched_.push_back(v);
    }
  };
  for (const int v : region_) {
    for (int k = triangle_starts_[v]; k < triangle_starts_[v + 1]; ++k) {
      const int t = triangle_list_[k];
      if (triangle_mark_[t]) continue;
      triangle_mark_[t] = 1;
      region_triangles_.push_back(t);
      for (int c = 0; c < 3; ++c) touch(model.triangles(c, t));
    }
    for (int k = hinge_starts_[v]; k < hinge_starts_[v + 1]; ++k) {
      const int e = hinge_list_[k];
      if (hinge_mark_[e]) continue;
      hinge_mark_[e] = 1;
      region_hinges_.push_back(e);
      for (int c = 0; c < 4; ++c) touch(model.bending.hinges(c, e));
    }
    touch(v);
  }
  return above;
}

double NewtonTail::worst_residual(const ClothModel& model, double h, const Positions& gradient) const {
  double worst = 0.0;
  for (const int i : touched_) worst = std::max(worst, h * gradient.col(i).norm() * model.inverse_mass[i]);
  return worst;
}

double NewtonTail::region_potential(const ClothModel& model, const Vec3& gravity, double h,
                                    const Positions& x_start, const Positions& x_hat,
                                    const Positions& x) const {
  double value = 0.0;
  for (const int t : region_triangles_) {
    value += membrane_energy(x.col(model.triangles(0, t)), x.col(model.triangles(1, t)),
                             x.col(model.triangles(2, t)), model.membrane.rest[t], model.membrane.material,
                             nullptr, nullptr, false);
  }
  for (const int e : region_hinges_) value += bending_element_energy(model.bending, e, x, nullptr);
  const double damping = model.mass_damping > 0.0 ? model.mass_damping / h : 0.0;
  for (const int i : region_) {
    const double m = model.mass[i];
    value += 0.5 * m / (h * h) * (x.col(i) - x_hat.col(i)).squaredNorm() +
             0.5 * damping * m * (x.col(i) - x_start.col(i)).squaredNorm() - m * gravity.dot(x.col(i));
    if (penalty_ != nullptr) value += penalty_->vertex_energy(i, x, nullptr, nullptr);
  }
  return value;
}

void NewtonTail::assemble_region(const ClothModel& model, double h, const Positions& x,
                                 SparseHessian& hessian, const HessianStencils& stencils) {
  hessian.zero_block_rows(region_);
  for (const int t : region_triangles_) {
    Matrix9d element;
    membrane_energy(x.col(model.triangles(0, t)), x.col(model.triangles(1, t)), x.col(model.triangles(2, t)),
                    model.membrane.rest[t], model.membrane.material, nullptr, &element, true);
    hessian.add_element<3>(stencils.triangles, t, element);
  }
  for (const int e : region_hinges_) {
    if (stencils.hinges < 0) break;  // the hinges' Hessian is left out of the matrix
    bending_element_energy(model.bending, e, x, nullptr, &hessian, stencils.hinges, /*project=*/true);
  }
  coupling_.clear();
  if (contact_ != nullptr) add_contact_blocks(hessian);
  const double damping = model.mass_damping > 0.0 ? model.mass_damping / h : 0.0;
  for (size_t k = 0; k < region_.size(); ++k) {
    const int i = region_[k];
    Mat3 block = (model.mass[i] * (1.0 / (h * h) + damping)) * Mat3::Identity();
    if (penalty_ != nullptr) penalty_->vertex_energy(i, x, nullptr, &block);
    hessian.add_vertex_block(i, block);
    inverse_blocks_[k] = hessian.diagonal_block(i).inverse();
  }
}

void NewtonTail::add_contact_blocks(SparseHessian& hessian) {
  const ContactBlocks& blocks = contact_blocks_;
  for (size_t c = 0; c < blocks.blocks.size(); ++c) {
    const std::array<int, 4>& vertices = blocks.vertices[c];
    const std::array<double, 4>& weights = blocks.weights[c];
    for (int j = 0; j < 4; ++j) {
      const int a = vertices[j] >= 0 ? local_[vertices[j]] : -1;
      if (a < 0 || weights[j] == 0.0) continue;
      hessian.add_vertex_block(vertices[j], (weights[j] * weights[j]) * blocks.blocks[c]);
      for (int k = j + 1; k < 4; ++k) {
        const int b = vertices[k] >= 0 ? local_[vertices[k]] : -1;
        if (b < 0 || weights[k] == 0.0) continue;
        const Mat3 block = (weights[j] * weights[k]) * blocks.blocks[c];
        if (a == b) {
          hessian.add_vertex_block(vertices[j], 2.0 * block);
        } else {
          coupling_.push_back({a, b, block});
        }
      }
    }
  }
}

Vec3 NewtonTail::vertex_gradient(const ClothModel& model, const Vec3& gravity, double h,
                                 const Positions& x_start, const Positions& x_hat, const Positions& x,
                                 int i) const {
  const double m = model.mass[i];
  const double damping = model.mass_damping > 0.0 ? model.mass_damping / h : 0.0;
  Vec3 g = m / (h * h) * (x.col(i) - x_hat.col(i)) + damping * m * (x.col(i) - x_start.col(i)) - m * gravity;
  if (penalty_ != nullptr) penalty_->vertex_energy(i, x, &g, nullptr);
  for (int k = triangle_starts_[i]; k < triangle_starts_[i + 1]; ++k) {
    const int t = triangle_list_[k];
    Vector9d element;
    membrane_energy(x.col(model.triangles(0, t)), x.col(model.triangles(1, t)), x.col(model.triangles(2, t)),
                    model.membrane.rest[t], model.membrane.material, &element, nullptr, false);
    g += element.segment<3>(3 * corner_of<3>(model.triangles, t, i));
  }
  for (int k = hinge_starts_[i]; k < hinge_starts_[i + 1]; ++k) {
    const int e = hinge_list_[k];
    Vector12d element;
    bending_element_energy(model.bending, e, x, &element);
    g += element.segment<3>(3 * corner_of<4>(model.bending.hinges, e, i));
  }
  return g;
}

void NewtonTail::update_contact_gradient(const ClothModel& model, const Positions& x, Positions& gradient,
                                         Positions& contact_gradient) {
  // Only the contacts with a region vertex change: their part now, against their part before.
  new_partial_gradient_.setZero();
  contact_->evaluate_moving(x, moving_, &new_partial_gradient_, nullptr);
  for (int i = 0; i < num_vertices_; ++i) {
    const Vec3 change = new_partial_gradient_.col(i) - partial_gradient_.col(i);
    contact_gradient.col(i) += change;
    if (model.inverse_mass[i] == 0.0) continue;
    // update_gradient() left the touched vertices without contact: they take it whole.
    gradient.col(i) += touched_mark_[i] ? Vec3(contact_gradient.col(i)) : change;
  }
  partial_gradient_.swap(new_partial_gradient_);
}

void NewtonTail::update_gradient(const ClothModel& model, const Vec3& gravity, double h,
                                 const Positions& x_start, const Positions& x_hat, const Positions& x,
                                 Positions& gradient) {
  for (const int i : touched_) {
    gradient.col(i) =
        model.inverse_mass[i] > 0.0 ? vertex_gradient(model, gravity, h, x_start, x_hat, x, i) : Vec3::Zero();
  }
}

bool NewtonTail::solve(const ClothModel& model, double h, const SparseHessian& hessian,
                       const NewtonTailSettings& settings) {
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(region_.size());
  auto dx = dx_.head(size);
  auto r = r_.head(size);
  auto z = z_.head(size);
  auto p = p_.head(size);
  auto q = q_.head(size);
  dx.setZero();
  r = -region_gradient_.head(size);
  // Relative to the start, and tight enough that what CG leaves is under half the tolerance on
  // every vertex (|r| bounds each vertex's h |r_i| / m_i once divided by the lightest mass).
  double lightest = std::numeric_limits<double>::infinity();
  for (const int i : region_) lightest = std::min(lightest, model.mass[i]);
  const double threshold =
      std::min(settings.cg_tolerance * r.norm(), 0.5 * settings.tolerance * lightest / h);
  const auto precondition = [&] {
    for (size_t k = 0; k < region_.size(); ++k)
      z.segment<3>(3 * k) = inverse_blocks_[k] * r.segment<3>(3 * k);
  };
  precondition();
  p = z;
  double rz = r.dot(z);
  for (int iteration = 0; iteration < settings.max_cg_iterations && r.norm() > threshold; ++iteration) {
    hessian.multiply_region(region_, local_, p_, q_);
    for (const Coupling& c : coupling_) {
      q.segment<3>(3 * c.a) += c.block * p.segment<3>(3 * c.b);
      q.segment<3>(3 * c.b) += c.block * p.segment<3>(3 * c.a);
    }
    const double curvature = p.dot(q);
    if (!(curvature > 0.0)) break;
    const double alpha = rz / curvature;
    dx += alpha * p;
    r -= alpha * q;
    precondition();
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return dx.allFinite() && dx.squaredNorm() > 0.0;
}

int NewtonTail::iterate(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                        const Positions& x_hat, const ContactPenalty* penalty, SolveContact* contact,
                        const NewtonTailSettings& settings, SparseHessian& hessian,
                        const HessianStencils& stencils, Positions& x, Positions& gradient,
                        Positions* contact_gradient) {
  penalty_ = penalty != nullptr && penalty->active() ? penalty : nullptr;
  contact_ = contact_gradient != nullptr ? contact : nullptr;
  collapsed_ = false;
  int free_vertices = 0;
  for (int i = 0; i < num_vertices_; ++i) free_vertices += model.inverse_mass[i] > 0.0;
  const double largest = settings.largest_share * free_vertices;
  int iterations = 0;
  while (iterations < settings.max_iterations) {
    const int above = collect_region(model, h, settings.tolerance, largest, gradient);
    if (above == 0 || above > largest) break;
    // The contact's energy at x and its blocks there (the pairs of the last segment, which holds x).
    double contact_before = 0.0;
    if (contact_ != nullptr) {
      partial_gradient_.setZero();
      contact_before = contact_->evaluate_moving(x, moving_, &partial_gradient_, &contact_blocks_);
    }
    assemble_region(model, h, x, hessian, stencils);
    for (size_t k = 0; k < region_.size(); ++k) region_gradient_.segment<3>(3 * k) = gradient.col(region_[k]);
    if (!solve(model, h, hessian, settings)) break;
    const Eigen::Index size = 3 * static_cast<Eigen::Index>(region_.size());
    const double slope = region_gradient_.head(size).dot(dx_.head(size));
    if (!(slope < 0.0)) break;
    // No trial goes past the step along which every pair keeps apart.
    double alpha = 1.0;
    if (contact_ != nullptr) {
      for (size_t k = 0; k < region_.size(); ++k) step_.col(region_[k]) = dx_.segment<3>(3 * k);
      alpha = contact_->max_step(x, step_);
      for (const int i : region_) step_.col(i).setZero();
    }
    const double before = region_potential(model, gravity, h, x_start, x_hat, x) + contact_before;
    for (const int i : region_) saved_.col(i) = x.col(i);
    bool accepted = false;
    for (; alpha > 1e-4; alpha *= 0.5) {
      for (size_t k = 0; k < region_.size(); ++k)
        x.col(region_[k]) = saved_.col(region_[k]) + alpha * dx_.segment<3>(3 * k);
      const double trial =
          region_potential(model, gravity, h, x_start, x_hat, x) +
          (contact_ != nullptr ? contact_->evaluate_moving(x, moving_, nullptr, nullptr) : 0.0);
      if (trial <= before + 1e-4 * alpha * slope) {  // false for NaN
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      for (const int i : region_) x.col(i) = saved_.col(i);
      break;
    }
    // Phi fell, but a step that raises the residual a hundredfold is a hinge's wing collapsing
    // towards zero height (its gradient grows as 1 / height): undone, and the tail stops.
    const double worst_before = worst_residual(model, h, gradient);
    update_gradient(model, gravity, h, x_start, x_hat, x, gradient);
    if (contact_ != nullptr) update_contact_gradient(model, x, gradient, *contact_gradient);
    if (worst_residual(model, h, gradient) > diverging_factor * worst_before) {
      for (const int i : region_) x.col(i) = saved_.col(i);
      update_gradient(model, gravity, h, x_start, x_hat, x, gradient);
      if (contact_ != nullptr) update_contact_gradient(model, x, gradient, *contact_gradient);
      collapsed_ = true;
      break;
    }
    ++iterations;
  }
  contact_ = nullptr;
  return iterations;
}

}  // namespace weft
