#include "physics/bending.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace weft {

BendingTerm make_bending_term(const MeshTopology& topology, const Positions& rest_positions, double stiffness,
                              BendingModel model) {
  BendingTerm term;
  term.stiffness = stiffness;
  term.hinges.resize(4, topology.num_hinges());
  int kept = 0;
  double largest_rest_angle = 0.0;
  for (int h = 0; h < topology.num_hinges(); ++h) {
    const Eigen::Vector4i hinge = topology.hinges.col(h);
    const Vec3 x0 = rest_positions.col(hinge[0]), x1 = rest_positions.col(hinge[1]);
    const Vec3 x2 = rest_positions.col(hinge[2]), x3 = rest_positions.col(hinge[3]);
    HingeRest rest;
    QuadraticHinge quadratic;
    try {
      rest = hinge_rest(x0, x1, x2, x3);
      quadratic = quadratic_hinge_rest(x0, x1, x2, x3);
    } catch (const std::invalid_argument&) {
      continue;  // a degenerate wing has no dihedral angle to keep
    }
    term.rest.push_back(rest);
    term.quadratic.push_back(quadratic);
    largest_rest_angle = std::max(largest_rest_angle, std::abs(rest.rest_angle));
    term.hinges.col(kept++) = hinge;
  }
  term.hinges.conservativeResize(4, kept);
  term.model = model;
  if (model == BendingModel::quadratic && !(largest_rest_angle <= flat_rest_angle)) {
    std::ostringstream message;
    message << "the quadratic bending model needs a flat rest mesh, but a hinge's rest angle is "
            << largest_rest_angle << " rad (flat: at most " << flat_rest_angle
            << "); use \"dihedral\"";
    throw std::invalid_argument(message.str());
  }
  if (model == BendingModel::quadratic) {
    term.rest.clear();
  } else {
    term.quadratic.clear();
  }
  term.coloring = ElementColoring(term.hinges, static_cast<int>(rest_positions.cols()));
  return term;
}

double bending_stiffness_rate(const BendingTerm& term, const Positions& rest_positions,
                              const Eigen::VectorXd& inverse_mass) {
  if (!term.enabled()) return 0.0;
  if (term.model == BendingModel::quadratic) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(rest_positions.cols());
  for (int h = 0; h < term.hinges.cols(); ++h) {
    const Eigen::Vector4i v = term.hinges.col(h);
    const HingeGaussNewton hinge = hinge_bending_gauss_newton(
        rest_positions.col(v[0]), rest_positions.col(v[1]), rest_positions.col(v[2]),
        rest_positions.col(v[3]), term.rest[h], term.stiffness);
    for (int k = 0; k < 4; ++k)
      diagonal[v[k]] += hinge.curvature * hinge.angle_gradient.segment<3>(3 * k).squaredNorm();
  }
  double rate = 0.0;
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) rate = std::max(rate, diagonal[i] * inverse_mass[i]);
  return rate;
}

double bending_element_energy(const BendingTerm& term, int h, const Positions& x, Vector12d* gradient,
                              SparseHessian* hessian, int stencil, bool project) {
  const Eigen::Vector4i v = term.hinges.col(h);
  if (term.model == BendingModel::quadratic) {
    const QuadraticHinge& hinge = term.quadratic[h];
    const double energy =
        quadratic_bending_energy(x.col(v[0]), x.col(v[1]), x.col(v[2]), x.col(v[3]), hinge, term.stiffness, gradient);
    if (hessian) {
      hessian->add_element_isotropic<4>(stencil, h, quadratic_bending_hessian_coefficients(hinge, term.stiffness));
    }
    return energy;
  }
  if (hessian && project) {  // Gauss-Newton: the rank-one Hessian goes into the blocks unformed
    const HingeGaussNewton hinge = hinge_bending_gauss_newton(x.col(v[0]), x.col(v[1]), x.col(v[2]), x.col(v[3]),
                                                              term.rest[h], term.stiffness);
    if (gradient) *gradient = hinge.gradient;
    hessian->add_element_outer<4>(stencil, h, hinge.curvature, hinge.angle_gradient);
    return hinge.energy;
  }
  Matrix12d element_hessian;
  const double energy = hinge_bending_energy(x.col(v[0]), x.col(v[1]), x.col(v[2]), x.col(v[3]), term.rest[h],
                                             term.stiffness, gradient, hessian ? &element_hessian : nullptr);
  if (hessian) hessian->add_element<4>(stencil, h, element_hessian);
  return energy;
}

double evaluate_bending(const BendingTerm& term, const Positions& x, Positions* gradient, SparseHessian* hessian,
                        int stencil, bool project) {
  return term.coloring.sum_over_elements(static_cast<int>(term.hinges.cols()), [&](int h) {
    Vector12d element_gradient;
    const double energy =
        bending_element_energy(term, h, x, gradient ? &element_gradient : nullptr, hessian, stencil, project);
    if (gradient) {
      // The hinge's 12 entries onto its four vertices' columns.
      for (int k = 0; k < 4; ++k) gradient->col(term.hinges(k, h)) += element_gradient.segment<3>(3 * k);
    }
    return energy;
  });
}

const char* to_string(BendingModel model) { return model == BendingModel::quadratic ? "quadratic" : "dihedral"; }

}  // namespace weft
