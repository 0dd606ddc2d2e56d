#pragma once
// Small spring cloths built inline for the integrator tests, and the linearised quantities the
// tests compare against (largest vibration frequency, total momentum).
#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/mesh_generators.hpp"
#include "physics/cloth.hpp"

namespace weft::test {

// An n x n lattice spring cloth `size` metres wide lying flat in the XZ plane at the origin
// (alternating triangulation), every vertex of mass `vertex_mass`, no pins, no damping.
inline Cloth spring_grid_cloth(int n, double size, double vertex_mass, const SpringStiffness& params) {
  TriangleMesh mesh = make_grid(n, n, size, size, GridTriangulation::alternating);
  transform_positions(mesh.positions, rotation_from_euler_degrees(Vec3(-90, 0, 0)), 1.0, Vec3::Zero());
  ClothModel model;
  model.springs = make_lattice_springs(n, n, GridTriangulation::alternating, mesh.positions, params);
  model.rest_positions = mesh.positions;
  model.triangles = mesh.triangles;
  model.mass = Eigen::VectorXd::Constant(n * n, vertex_mass);
  model.inverse_mass = model.mass.cwiseInverse();
  model.grid_nx = model.grid_ny = n;
  return make_cloth(std::move(model));
}

inline SpringStiffness spring_params(double structural, double shear, double bend, double damping = 0.0) {
  SpringStiffness params;
  params.stiffness[0] = structural;
  params.stiffness[1] = shear;
  params.stiffness[2] = bend;
  for (double& gamma : params.damping) gamma = damping;
  return params;
}

// Sets vertex masses (and inverse masses, keeping pins at 0).
inline void set_masses(ClothModel& model, const Eigen::VectorXd& mass) {
  for (Eigen::Index i = 0; i < mass.size(); ++i) {
    if (model.inverse_mass[i] != 0.0) model.inverse_mass[i] = 1.0 / mass[i];
  }
  model.mass = mass;
}

// Largest angular frequency of the free vertices linearised at x: sqrt(max eig(M^-1/2 K M^-1/2))
// with K the (unprojected) spring stiffness matrix; the symplectic Euler step must stay below
// 2 / this value.
inline double largest_frequency(const ClothModel& model, const Positions& x) {
  const int n = static_cast<int>(model.mass.size());
  Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int s = 0; s < model.springs.size(); ++s) {
    const int i = model.springs.vertices(0, s), j = model.springs.vertices(1, s);
    const Mat3 block = spring_hessian_block(x.col(j) - x.col(i), model.springs.rest_length[s],
                                            model.springs.stiffness[s], /*project_to_psd=*/false);
    stiffness.block<3, 3>(3 * i, 3 * i) += block;
    stiffness.block<3, 3>(3 * j, 3 * j) += block;
    stiffness.block<3, 3>(3 * i, 3 * j) -= block;
    stiffness.block<3, 3>(3 * j, 3 * i) -= block;
  }
  // Scaling by sqrt(inverse mass) drops pinned vertices (inverse mass 0).
  Eigen::VectorXd scale(3 * n);
  for (int i = 0; i < n; ++i) scale.segment<3>(3 * i).setConstant(std::sqrt(model.inverse_mass[i]));
  const Eigen::MatrixXd scaled = scale.asDiagonal() * stiffness * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled, Eigen::EigenvaluesOnly);
  return std::sqrt(eigen.eigenvalues().maxCoeff());
}

inline Vec3 total_momentum(const Cloth& cloth) { return cloth.state.v * cloth.model.mass; }

}  // namespace weft::test
