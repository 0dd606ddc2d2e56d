#include "physics/xpbd.hpp"

#include <cmath>

#include "core/topology.hpp"
#include "physics/air_drag.hpp"
#include "physics/volume_pressure.hpp"

namespace weft {

namespace {

// One XPBD update of the element with vertices `v`, energy `energy` and energy gradient
// `gradient` (vertices stacked): the constraint C = sqrt(2 E) with compliance 1 (see xpbd.hpp).
template <int N>
void project_element(const int (&v)[N], double energy, const Eigen::Matrix<double, 3 * N, 1>& gradient,
                     const Eigen::VectorXd& inverse_mass, double alpha_tilde, double& lambda, Positions& x) {
  if (!(energy > 0.0)) return;  // at rest (or not finite: left to the divergence check)
  const double c = std::sqrt(2.0 * energy);
  // grad C = grad E / C.
  double denominator = alpha_tilde;
  for (int k = 0; k < N; ++k) denominator += inverse_mass[v[k]] * gradient.template segment<3>(3 * k).squaredNorm() / (c * c);
  const double dlambda = (-c - alpha_tilde * lambda) / denominator;
  lambda += dlambda;
  const double scale = dlambda / c;
  for (int k = 0; k < N; ++k) x.col(v[k]) += (inverse_mass[v[k]] * scale) * gradient.template segment<3>(3 * k);
}

// One update of the distance constraint C = |xj - xi| - rest_length with scaled compliance
// alpha~ (chosen by `compression_alpha` when C < 0) and XPBD's damping gamma~ (Macklin et al.
// 2016, eq. 26; 0 for none) on the motion since x_prev.
void project_distance(int i, int j, double rest_length, double alpha, double compression_alpha, double gamma,
                      const Eigen::VectorXd& w, const Positions& x_prev, double& lambda, Positions& x) {
  const Vec3 d = x.col(j) - x.col(i);
  const double length = d.norm();
  if (!(length > 0.0)) return;
  const Vec3 n = d / length;  // grad_j C = n, grad_i C = -n
  const double c = length - rest_length;
  const double a = c < 0.0 ? compression_alpha : alpha;
  const double rate = gamma == 0.0 ? 0.0 : n.dot((x.col(j) - x_prev.col(j)) - (x.col(i) - x_prev.col(i)));
  const double dlambda = (-c - a * lambda - gamma * rate) / ((1.0 + gamma) * (w[i] + w[j]) + a);
  if (!std::isfinite(dlambda)) return;  // both ends pinned
  lambda += dlambda;
  x.col(i) -= (w[i] * dlambda) * n;
  x.col(j) += (w[j] * dlambda) * n;
}

// Damping gamma ((vj - vi) . d) d / |d|^2 on i (and its opposite on j) of the springs without
// stiffness, added to `force` (springs with stiffness are damped implicitly in sweep()).
void add_spring_damping_forces(const SpringSet& springs, const Positions& x, const Positions& v, Positions& force) {
  for (int s = 0; s < springs.size(); ++s) {
    if (springs.damping[s] == 0.0 || springs.stiffness[s] > 0.0) continue;  // the others damp in sweep()
    const int i = springs.vertices(0, s), j = springs.vertices(1, s);
    const Vec3 d = x.col(j) - x.col(i);
    const double length_squared = d.squaredNorm();
    if (!(length_squared > 0.0)) continue;
    const Vec3 f = springs.damping[s] * (v.col(j) - v.col(i)).dot(d) / length_squared * d;
    force.col(i) += f;
    force.col(j) -= f;
  }
}

bool any_spring_damping(const SpringSet& springs) {
  return springs.size() > 0 && (springs.damping.array() != 0.0 && springs.stiffness.array() == 0.0).any();
}

}  // namespace

// Membrane edges with van Gelder's (1998) stiffness k = E t sum_T A_T / L^2 over the one or two
// rest triangles at the edge. Only the geometric factor sum_T A_T / L^2 is kept: E, t and the
// compression factor are read from the material at every sweep, so live edits take effect.
void XpbdSolver::prepare(const ClothModel& model) {
  prepared_vertices_ = static_cast<int>(model.rest_positions.cols());
  prepared_triangles_ = static_cast<int>(model.triangles.cols());
  edges_.resize(2, 0);
  if (!model.membrane.enabled()) return;
  const MeshTopology topology = build_topology(model.triangles, prepared_vertices_);
  edges_ = topology.edges;
  const Eigen::Index n = edges_.cols();
  edge_rest_length_.resize(n);
  edge_area_over_length2_.resize(n);
  for (Eigen::Index e = 0; e < n; ++e) {
    const double length = (model.rest_positions.col(edges_(1, e)) - model.rest_positions.col(edges_(0, e))).norm();
    double area = 0.0;
    for (int side = 0; side < 2; ++side) {
      const int t = topology.edge_triangles(side, e);
      if (t >= 0) area += model.membrane.rest[t].area;
    }
    edge_rest_length_[e] = length;
    edge_area_over_length2_[e] = area / (length * length);
  }
}

void XpbdSolver::step(Cloth& cloth, const Vec3& gravity, double h, const XpbdSettings& settings) {
  const ClothModel& model = cloth.model;
  if (prepared_vertices_ != model.rest_positions.cols() || prepared_triangles_ != model.triangles.cols()) {
    prepare(model);
  }
  ClothState& state = cloth.state;
  const int substeps = std::max(1, settings.substeps);
  const double hs = h / substeps;
  spring_lambda_.resize(static_cast<size_t>(model.springs.size()));
  edge_lambda_.resize(static_cast<size_t>(edges_.cols()));
  hinge_lambda_.resize(static_cast<size_t>(model.bending.hinges.cols()));
  for (int substep = 0; substep < substeps; ++substep) {
    predict(model, state, gravity, hs);
    x_prev_ = state.x;
    state.x.noalias() += hs * state.v;
    std::fill(spring_lambda_.begin(), spring_lambda_.end(), 0.0);
    std::fill(edge_lambda_.begin(), edge_lambda_.end(), 0.0);
    std::fill(hinge_lambda_.begin(), hinge_lambda_.end(), 0.0);
    for (int iteration = 0; iteration < std::max(1, settings.iterations); ++iteration) sweep(model, state.x, hs);
    state.v = (state.x - x_prev_) / hs;
  }
}

// Step 1 of xpbd.hpp: gravity and the forces that are not constraints, explicitly; then mass damping.
void XpbdSolver::predict(const ClothModel& model, ClothState& state, const Vec3& gravity, double hs) {
  const bool spring_damping = any_spring_damping(model.springs);
  if (model.air_drag.enabled() || model.pressure.enabled || spring_damping) {
    other_force_.setZero(3, state.x.cols());
    if (model.pressure.enabled) {
      evaluate_pressure(model.pressure, model.triangles, state.x, &other_force_, nullptr, -1, false);
      other_force_ = -other_force_;  // the gradient was added
    }
    if (model.air_drag.enabled()) add_air_drag_forces(model.air_drag, model.triangles, state.x, state.v, other_force_);
    if (spring_damping) add_spring_damping_forces(model.springs, state.x, state.v, other_force_);
    state.v.noalias() += hs * (other_force_ * model.inverse_mass.asDiagonal());
  }
  const double damping = 1.0 / (1.0 + model.mass_damping * hs);
  for (Eigen::Index i = 0; i < state.v.cols(); ++i) {
    if (model.inverse_mass[i] == 0.0) continue;  // pins keep their (scripted) velocity
    state.v.col(i) = damping * (state.v.col(i) + hs * gravity);
  }
}

// Step 3 of xpbd.hpp: one Gauss-Seidel sweep over every elastic element.
void XpbdSolver::sweep(const ClothModel& model, Positions& x, double hs) {
  const double alpha_tilde = 1.0 / (hs * hs);  // compliance 1 scaled by the sub-step
  const Eigen::VectorXd& w = model.inverse_mass;
  // Springs: C = l - L with compliance 1/k and XPBD's damping (Macklin et al. 2016, eq. 26) for
  // the spring damping gamma, gamma~ = gamma / (k hs): implicit, so stable for any gamma.
  const SpringSet& springs = model.springs;
  for (int s = 0; s < springs.size(); ++s) {
    const double k = springs.stiffness[s];
    if (!(k > 0.0)) continue;  // damping-only springs act explicitly in predict()
    const double alpha = alpha_tilde / k;
    project_distance(springs.vertices(0, s), springs.vertices(1, s), springs.rest_length[s], alpha, alpha,
                     springs.damping[s] / (k * hs), w, x_prev_, spring_lambda_[s], x);
  }
  // Membrane edges: the same constraint with compliance 1/k, 1/compression_factor softer in compression.
  const MembraneMaterial& material = model.membrane.material;
  const double alpha_per_factor = alpha_tilde / (material.young_modulus * material.thickness);
  for (Eigen::Index e = 0; e < edges_.cols(); ++e) {
    const double alpha = alpha_per_factor / edge_area_over_length2_[e];
    project_distance(edges_(0, e), edges_(1, e), edge_rest_length_[e], alpha, alpha / material.compression_factor,
                     0.0, w, x_prev_, edge_lambda_[e], x);
  }
  if (model.bending.enabled()) {
    Vector12d gradient;
    for (Eigen::Index e = 0; e < model.bending.hinges.cols(); ++e) {
      const Eigen::Vector4i hinge = model.bending.hinges.col(e);
      const int v[4] = {hinge[0], hinge[1], hinge[2], hinge[3]};
      const double energy = bending_element_energy(model.bending, static_cast<int>(e), x, &gradient);
      project_element<4>(v, energy, gradient, w, alpha_tilde, hinge_lambda_[e], x);
    }
  }
}

}  // namespace weft
