#include "physics/membrane_stvk.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace weft {

namespace {

constexpr double sqrt2 = 1.41421356237309504880;

using Matrix32d = Eigen::Matrix<double, 3, 2>;

// Principal values of the symmetric [[a, b], [b, d]] and the direction of the larger one,
// v_max = (cos t, sin t) with t = atan2(2b, a - d)/2, kept as cos 2t and sin 2t (no trig).
struct Principal {
  double e_max;
  double e_min;
  double radius;  // (e_max - e_min)/2
  double cos2;
  double sin2;
};

Principal principal(double a, double b, double d) {
  const double half_difference = 0.5 * (a - d);
  const double radius = std::sqrt(half_difference * half_difference + b * b);
  const double mean = 0.5 * (a + d);
  Principal p{mean + radius, mean - radius, radius, 1.0, 0.0};
  if (radius > 0.0) {
    p.cos2 = half_difference / radius;
    p.sin2 = b / radius;
  }
  return p;
}

// v_max v_max^T = [[cos^2 t, cos t sin t], [cos t sin t, sin^2 t]]; v_min v_min^T = I - that.
Eigen::Matrix2d max_projector(const Principal& p) {
  const double cs = 0.5 * p.sin2;
  Eigen::Matrix2d m;
  m << 0.5 * (1.0 + p.cos2), cs, cs, 0.5 * (1.0 - p.cos2);
  return m;
}

Matrix32d deformation_gradient(const Vec3& x0, const Vec3& x1, const Vec3& x2, const MembraneRest& rest) {
  Matrix32d ds;
  ds << x1 - x0, x2 - x0;
  return ds * rest.dm_inverse;
}

// E = (F^T F - I)/2, built from column dot products so that it is exactly symmetric.
Eigen::Matrix2d green_strain_of(const Matrix32d& f) {
  const double off_diagonal = 0.5 * f.col(0).dot(f.col(1));
  Eigen::Matrix2d e;
  e << 0.5 * (f.col(0).squaredNorm() - 1.0), off_diagonal, off_diagonal, 0.5 * (f.col(1).squaredNorm() - 1.0);
  return e;
}

}  // namespace

MembraneRest membrane_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2) {
  const Vec3 e1 = x1 - x0;
  const Vec3 e2 = x2 - x0;
  const double twice_area = e1.cross(e2).norm();
  if (!(twice_area > 1e-14 * std::max(e1.squaredNorm(), e2.squaredNorm())) || !std::isfinite(twice_area)) {
    throw std::invalid_argument("membrane_rest: triangle has zero area");
  }
  // Rest edges in the frame (t, b): t along e1, b in the plane, perpendicular to t.
  const double length1 = e1.norm();
  Eigen::Matrix2d dm;
  dm << length1, e2.dot(e1) / length1, 0.0, twice_area / length1;
  return MembraneRest{dm.inverse(), 0.5 * twice_area};
}

Eigen::Matrix2d green_strain(const Vec3& x0, const Vec3& x1, const Vec3& x2, const MembraneRest& rest) {
  return green_strain_of(deformation_gradient(x0, x1, x2, rest));
}

double largest_principal_strain(const Eigen::Matrix2d& strain) {
  return principal(strain(0, 0), strain(0, 1), strain(1, 1)).e_max;
}

double membrane_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const MembraneRest& rest,
                       const MembraneMaterial& material, Vector9d* gradient, Matrix9d* hessian, bool psd) {
  const Matrix32d f = deformation_gradient(x0, x1, x2, rest);
  const Eigen::Matrix2d strain = green_strain_of(f);
  const double young = material.young_modulus;
  const double nu = material.poisson_ratio;
  const double mu = young / (2.0 * (1.0 + nu));
  const double lambda = young * nu / (1.0 - nu * nu);
  const double c = material.compression_factor;
  const double a = strain(0, 0);
  const double b = strain(0, 1);
  const double d = strain(1, 1);
  const Principal p = principal(a, b, d);

  // psi, the stress S = dpsi/dE and the tangent C = d2psi/dE2, symmetric tensors in Mandel
  // notation (E11, E22, sqrt2 E12) so that S : dE = s . de and dE : C : dE = de^T C de.
  double psi;
  Eigen::Vector3d stress;
  Eigen::Matrix3d tangent;
  // Spectral derivatives (Daleckii-Krein) in the principal frame: S = diag(g'(e_i)) and
  // C = diag(g''(e_max), g''(e_min), (g'(e_max) - g'(e_min))/(e_max - e_min)), given here as
  // the principal stresses s_max, s_min and that diagonal, rotated into the Mandel frame.
  const auto set_from_principal = [&](double s_max, double s_min, const Eigen::Vector3d& principal_tangent) {
    const double cc = 0.5 * (1.0 + p.cos2);
    const double ss = 0.5 * (1.0 - p.cos2);
    const double cs = 0.5 * p.sin2;
    // S = s_max v_max v_max^T + s_min v_min v_min^T.
    stress << s_max * cc + s_min * ss, s_max * ss + s_min * cc, sqrt2 * (s_max - s_min) * cs;
    // Mandel rotation into the principal frame (orthogonal), de_principal = q de.
    Eigen::Matrix3d q;
    q << cc, ss, sqrt2 * cs, ss, cc, -sqrt2 * cs, -sqrt2 * cs, sqrt2 * cs, cc - ss;
    tangent.noalias() = q.transpose() * principal_tangent.asDiagonal() * q;
  };
  // With a smallest stretch s0 (min_stretch > 0), a principal strain past e0 = (s0^2 - 1)/2 is
  // resisted at the full stiffness again: g(t) = c t^2 + (1 - c)(t - e0)^2 for t < e0 (C1 at e0,
  // convex), so that a triangle cannot be flattened for next to nothing (a flat wing makes a
  // hinge's gradient grow as 1 / height).
  const double e0 = material.min_stretch > 0.0
                        ? 0.5 * (material.min_stretch * material.min_stretch - 1.0)
                        : -std::numeric_limits<double>::infinity();
  if (p.e_min < e0) {
    const auto g = [&](double t) {
      return t >= 0.0 ? t * t : c * t * t + (t < e0 ? (1.0 - c) * (t - e0) * (t - e0) : 0.0);
    };
    const auto dg = [&](double t) {
      return t >= 0.0 ? 2.0 * t : 2.0 * c * t + (t < e0 ? 2.0 * (1.0 - c) * (t - e0) : 0.0);
    };
    const auto ddg = [&](double t) { return t >= 0.0 ? 2.0 : (t < e0 ? 2.0 : 2.0 * c); };
    psi = mu * (g(p.e_max) + g(p.e_min));
    // Equal principal strains take the second derivative for the divided difference.
    const double divided = p.radius > 1e-12 * (1.0 + std::abs(p.e_min))
                               ? 0.5 * (dg(p.e_max) - dg(p.e_min)) / p.radius
                               : 0.5 * (ddg(p.e_max) + ddg(p.e_min));
    set_from_principal(mu * dg(p.e_max), mu * dg(p.e_min),
                       Eigen::Vector3d(mu * ddg(p.e_max), mu * ddg(p.e_min), mu * divided));
  } else if (p.e_min >= 0.0 || p.e_max <= 0.0) {
    // Both principal strains on one side of zero: the split is trivial, psi_mu = k mu |E|^2.
    const double k = p.e_min >= 0.0 ? 1.0 : c;
    psi = k * mu * (a * a + d * d + 2.0 * b * b);
    stress = 2.0 * k * mu * Eigen::Vector3d(a, d, sqrt2 * b);
    tangent = 2.0 * k * mu * Eigen::Matrix3d::Identity();
  } else {
    // e_max > 0 > e_min: psi_mu = mu (g(e_max) + g(e_min)), g(t) = t^2 (t > 0), c t^2 (t < 0).
    // The divided difference (e_max - c e_min)/r lies in [2c, 2] because r = (e_max - e_min)/2 > |e_i|.
    psi = mu * (p.e_max * p.e_max + c * p.e_min * p.e_min);
    set_from_principal(2.0 * mu * p.e_max, 2.0 * mu * c * p.e_min,
                       Eigen::Vector3d(2.0 * mu, 2.0 * mu * c, mu * (p.e_max - c * p.e_min) / p.radius));
  }
  // Volumetric part lambda/2 g(tr E).
  const double trace = a + d;
  const double kt = trace >= 0.0 ? 1.0 : c;
  psi += 0.5 * lambda * kt * trace * trace;
  stress.head<2>().array() += lambda * kt * trace;
  tangent.topLeftCorner<2, 2>().array() += lambda * kt;

  const double volume = rest.area * material.thickness;
  if (!gradient && !hessian) return volume * psi;

  // dF_j = sum_v w(j, v) dx_v (F = Ds Dm^-1, rows of Dm^-1 weight x1 - x0 and x2 - x0); the
  // weights of each row sum to zero (a translation does not strain the triangle).
  const Eigen::Matrix2d& dinv = rest.dm_inverse;
  Eigen::Matrix<double, 2, 3> w;
  w << -(dinv(0, 0) + dinv(1, 0)), dinv(0, 0), dinv(1, 0), -(dinv(0, 1) + dinv(1, 1)), dinv(0, 1), dinv(1, 1);
  // The stress as a tensor, S = [[s11, s12], [s12, s22]].
  Eigen::Matrix2d stress_matrix;
  stress_matrix << stress(0), stress(2) / sqrt2, stress(2) / sqrt2, stress(1);
  // dpsi = S : dE with dE = sym(F^T dF): vertex v's gradient is F S w_v (first Piola stress times
  // the vertex's weights).
  if (gradient) {
    const Matrix32d piola = volume * (f * stress_matrix);
    for (int v = 0; v < 3; ++v) gradient->segment<3>(3 * v).noalias() = piola * w.col(v);
  }
  if (hessian) {
    // Material part. Vertex v changes the strain (Mandel) by de = A_v F^T dx_v with
    // A_v = [[w0v, 0], [0, w1v], [w1v, w0v]/sqrt2] (column a weighs f_a . dx_v), so block (v, u)
    // of l^T C l is sum_ab K_ab f_a f_b^T with K = A_v^T C A_u, a 2x2 matrix per block: the 3x3
    // outer products f_a f_b^T are formed once. Geometric part S : sym(dF^T dF'): (w^T S w)(v, u)
    // I3. Blocks of vertices 1 and 2 are formed; vertex 0's follow because the weights sum to zero.
    if (psd) {
      const Principal s = principal(stress_matrix(0, 0), stress_matrix(0, 1), stress_matrix(1, 1));
      if (s.e_max <= 0.0) {
        stress_matrix.setZero();
      } else if (s.e_min < 0.0) {
        stress_matrix = s.e_max * max_projector(s);
      }
    }
    // Index k = v - 1 for vertices v = 1, 2.
    Eigen::Matrix<double, 3, 2> mandel[2];
    Eigen::Matrix<double, 3, 2> tangent_mandel[2];
    for (int k = 0; k < 2; ++k) {
      const double w0 = w(0, k + 1), w1 = w(1, k + 1);
      mandel[k] << w0, 0.0, 0.0, w1, w1 / sqrt2, w0 / sqrt2;
      tangent_mandel[k].noalias() = volume * (tangent * mandel[k]);
    }
    const Eigen::Matrix3d f00 = f.col(0) * f.col(0).transpose();
    const Eigen::Matrix3d f11 = f.col(1) * f.col(1).transpose();
    const Eigen::Matrix3d f01 = f.col(0) * f.col(1).transpose();
    const Eigen::Matrix2d geometric =
        volume * (w.rightCols<2>().transpose() * stress_matrix * w.rightCols<2>());
    // Block (v, u) of the Hessian for vertices v, u in {1, 2}.
    const auto block = [&](int v, int u) {
      const Eigen::Matrix2d k = mandel[v - 1].transpose() * tangent_mandel[u - 1];
      Eigen::Matrix3d b = k(0, 0) * f00 + k(1, 1) * f11 + k(0, 1) * f01 + k(1, 0) * f01.transpose();
      b.diagonal().array() += geometric(v - 1, u - 1);
      return b;
    };
    const Eigen::Matrix3d b11 = block(1, 1);
    const Eigen::Matrix3d b12 = block(1, 2);
    const Eigen::Matrix3d b22 = block(2, 2);
    const Eigen::Matrix3d b01 = -(b11 + b12.transpose());  // block (0, 1) = -(blocks (1, 1) + (2, 1))
    const Eigen::Matrix3d b02 = -(b12 + b22);              // block (0, 2) = -(blocks (1, 2) + (2, 2))
    hessian->block<3, 3>(0, 0) = -(b01 + b02);
    hessian->block<3, 3>(0, 3) = b01;
    hessian->block<3, 3>(0, 6) = b02;
    hessian->block<3, 3>(3, 0) = b01.transpose();
    hessian->block<3, 3>(3, 3) = b11;
    hessian->block<3, 3>(3, 6) = b12;
    hessian->block<3, 3>(6, 0) = b02.transpose();
    hessian->block<3, 3>(6, 3) = b12.transpose();
    hessian->block<3, 3>(6, 6) = b22;
  }
  return volume * psi;
}

bool apply_plastic_yield(const Vec3& x0, const Vec3& x1, const Vec3& x2, MembraneRest& rest,
                         double yield_strain, double flow_fraction) {
  if (!(yield_strain >= 0.0) || !(flow_fraction >= 0.0 && flow_fraction <= 1.0)) {
    throw std::invalid_argument("apply_plastic_yield: needs yield_strain >= 0 and flow_fraction in [0, 1]");
  }
  const Eigen::Matrix2d strain = green_strain(x0, x1, x2, rest);
  const Principal p = principal(strain(0, 0), strain(0, 1), strain(1, 1));
  if (!(std::max(std::abs(p.e_max), std::abs(p.e_min)) > yield_strain) || flow_fraction == 0.0) return false;
  if (!(1.0 + 2.0 * p.e_min > 1e-12)) return false;  // collapsed: no metric to flow towards

  // Target strain t with the excess over the yield strain shrunk by flow_fraction; the rest
  // stretch rho = sqrt((1 + 2e)/(1 + 2t)) makes the new Green strain exactly t.
  const auto rest_stretch = [&](double e) {
    const double excess = std::abs(e) - yield_strain;
    const double t = excess > 0.0 ? std::copysign(yield_strain + (1.0 - flow_fraction) * excess, e) : e;
    return std::sqrt((1.0 + 2.0 * e) / (1.0 + 2.0 * t));
  };
  const double rho_max = rest_stretch(p.e_max);
  const double rho_min = rest_stretch(p.e_min);

  // New rest edges U Dm: dm_inverse <- dm_inverse U^-1, area <- area det U.
  const Eigen::Matrix2d projector = max_projector(p);
  const Eigen::Matrix2d u_inverse = projector / rho_max + (Eigen::Matrix2d::Identity() - projector) / rho_min;
  rest.dm_inverse = (rest.dm_inverse * u_inverse).eval();
  rest.area *= rho_max * rho_min;
  return true;
}

MembraneTerm make_membrane_term(const Triangles& triangles, const Positions& rest_positions,
                                const MembraneMaterial& material, double yield_strain, double plastic_flow) {
  MembraneTerm term;
  term.material = material;
  term.yield_strain = yield_strain;
  term.plastic_flow = plastic_flow;
  term.rest.reserve(triangles.cols());
  term.coloring = ElementColoring(triangles, static_cast<int>(rest_positions.cols()));
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    try {
      term.rest.push_back(membrane_rest(rest_positions.col(triangles(0, t)),
                                        rest_positions.col(triangles(1, t)),
                                        rest_positions.col(triangles(2, t))));
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("triangle " + std::to_string(t) +
                                  " has zero area, so it has no membrane rest shape");
    }
  }
  return term;
}

double evaluate_membrane(const MembraneTerm& term, const Triangles& triangles, const Positions& x,
                         Positions* gradient, SparseHessian* hessian, int stencil, bool project) {
  return term.coloring.sum_over_elements(static_cast<int>(triangles.cols()), [&](int t) {
    Vector9d element_gradient;
    Matrix9d element_hessian;
    const int i0 = triangles(0, t), i1 = triangles(1, t), i2 = triangles(2, t);
    const double energy = membrane_energy(x.col(i0), x.col(i1), x.col(i2), term.rest[t], term.material,
                                          gradient ? &element_gradient : nullptr,
                                          hessian ? &element_hessian : nullptr, project);
    if (gradient) {
      gradient->col(i0) += element_gradient.segment<3>(0);
      gradient->col(i1) += element_gradient.segment<3>(3);
      gradient->col(i2) += element_gradient.segment<3>(6);
    }
    if (hessian) hessian->add_element<3>(stencil, t, element_hessian);
    return energy;
  });
}

int apply_membrane_plasticity(MembraneTerm& term, const Triangles& triangles, const Positions& x) {
  int yielded = 0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    yielded += apply_plastic_yield(x.col(triangles(0, t)), x.col(triangles(1, t)), x.col(triangles(2, t)),
                                   term.rest[t], term.yield_strain, term.plastic_flow);
  }
  return yielded;
}

}  // namespace weft
