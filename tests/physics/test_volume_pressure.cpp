// Volume and pressure: per-triangle signed volume derivatives by Taylor tests, the enclosed
// volume of closed meshes, the vertex gradient as area-weighted normals / 3, and the pressure
// law composed with the volume over a whole closed mesh.
#include "physics/volume_pressure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/mesh_generators.hpp"
#include "support/taylor.hpp"

namespace weft {
namespace {

using weft::testing::all_near_quarter;
using weft::testing::halving_ratios;

double volume_of(const Vector9d& q, Vector9d* gradient = nullptr, Matrix9d* hessian = nullptr) {
  return triangle_signed_volume(q.segment<3>(0), q.segment<3>(3), q.segment<3>(6), gradient, hessian);
}

TEST(VolumePressure, TriangleVolumeDerivativesTaylorTest) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 5; ++trial) {
    Vector9d q, direction;
    for (int i = 0; i < 9; ++i) q[i] = normal(rng), direction[i] = normal(rng);
    Vector9d gradient;
    Matrix9d hessian;
    const double volume = volume_of(q, &gradient, &hessian);
    const auto volume_remainder = [&](double a) {
      return std::abs(volume_of(q + a * direction) - volume - a * gradient.dot(direction));
    };
    const auto gradient_remainder = [&](double a) {
      Vector9d moved;
      volume_of(q + a * direction, &moved);
      return (moved - gradient - a * hessian * direction).norm();
    };
    EXPECT_TRUE(all_near_quarter(halving_ratios(volume_remainder, 1e-2, 5)));
    EXPECT_TRUE(all_near_quarter(halving_ratios(gradient_remainder, 1e-2, 5)));
    EXPECT_LE((hessian - hessian.transpose()).norm(), 1e-10 * hessian.norm());
  }
}

// Enclosed volume of a mesh and its gradient (3 x n_vertices).
double mesh_volume(const TriangleMesh& mesh, Positions* gradient) {
  double volume = 0.0;
  if (gradient) gradient->setZero(3, mesh.num_vertices());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3i v = mesh.triangles.col(t);
    Vector9d g;
    volume += triangle_signed_volume(mesh.positions.col(v[0]), mesh.positions.col(v[1]), mesh.positions.col(v[2]),
                                     gradient ? &g : nullptr, nullptr);
    if (gradient) {
      for (int k = 0; k < 3; ++k) gradient->col(v[k]) += g.segment<3>(3 * k);
    }
  }
  return volume;
}

TEST(VolumePressure, ClosedBoxVolumeAndAreaWeightedNormalGradient) {
  const Vec3 half(0.5, 0.75, 1.25);
  TriangleMesh box = make_box(half);
  transform_positions(box.positions, Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix(), 1.0,
                      Vec3(3.0, -2.0, 5.0));  // volume does not depend on the origin
  Positions gradient;
  EXPECT_NEAR(mesh_volume(box, &gradient), 8.0 * half.prod(), 1e-12);

  // dV/dx_i = sum over incident triangles of A_t n_t / 3 = (x1 - x0) x (x2 - x0) / 6.
  Positions expected = Positions::Zero(3, box.num_vertices());
  for (int t = 0; t < box.num_triangles(); ++t) {
    const Eigen::Vector3i v = box.triangles.col(t);
    const Vec3 x0 = box.positions.col(v[0]), x1 = box.positions.col(v[1]), x2 = box.positions.col(v[2]);
    const Vec3 area_normal = 0.5 * (x1 - x0).cross(x2 - x0);
    for (int k = 0; k < 3; ++k) expected.col(v[k]) += area_normal / 3.0;
  }
  EXPECT_LE((gradient - expected).norm(), 1e-12);
}

TEST(VolumePressure, SphereVolumeApproachesTheBall) {
  const TriangleMesh sphere = make_uv_sphere(0.8, 64, 32);
  const double ball = 4.0 / 3.0 * pi * std::pow(0.8, 3);
  const double volume = mesh_volume(sphere, nullptr);
  EXPECT_LT(volume, ball);  // inscribed polyhedron
  EXPECT_GT(volume, 0.99 * ball);
}

TEST(VolumePressure, PressureLawValueAndDerivatives) {
  PressureLaw law;
  law.bulk_modulus = 2e3;
  law.rest_volume = 0.4;
  law.pressure_scale = 1.5;
  const double target = law.pressure_scale * law.rest_volume;
  double slope, curvature;
  EXPECT_EQ(pressure_energy(target, law, &slope, &curvature), 0.0);
  EXPECT_EQ(slope, 0.0);
  EXPECT_NEAR(curvature, 2e3 / target, 1e-12);
  // Squeezed below the target: the pressure -dE/dV pushes outwards.
  const double squeezed = 0.45;
  EXPECT_NEAR(pressure_energy(squeezed, law, &slope, nullptr), 0.5 * 2e3 * (target - squeezed) * (target - squeezed) / target, 1e-12);
  EXPECT_LT(slope, 0.0);
  const double h = 1e-5;
  const double central = (pressure_energy(squeezed + h, law, nullptr, nullptr) -
                          pressure_energy(squeezed - h, law, nullptr, nullptr)) / (2.0 * h);
  EXPECT_NEAR(slope, central, 1e-6 * std::abs(slope));
  law.pressure_scale = 0.0;
  EXPECT_THROW(pressure_energy(1.0, law, nullptr, nullptr), std::invalid_argument);
}

TEST(VolumePressure, PressureEnergyOfAClosedMeshTaylorTest) {
  // E(V(x)): gradient E' dV/dx, Hessian E'' dV/dx dV/dx^T + E' d2V/dx2 (assembled densely here).
  TriangleMesh sphere = make_uv_sphere(1.0, 6, 4);
  const int n = 3 * sphere.num_vertices();
  PressureLaw law;
  law.bulk_modulus = 5.0;
  law.rest_volume = mesh_volume(sphere, nullptr);
  law.pressure_scale = 1.3;
  std::mt19937 rng(9);
  std::normal_distribution<double> normal;
  Eigen::VectorXd direction(n);
  for (int i = 0; i < n; ++i) direction[i] = normal(rng);

  const auto evaluate = [&](const Eigen::VectorXd& q, Eigen::VectorXd* gradient, Eigen::MatrixXd* hessian) {
    Eigen::VectorXd volume_gradient = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd volume_hessian = Eigen::MatrixXd::Zero(n, n);
    double volume = 0.0;
    for (int t = 0; t < sphere.num_triangles(); ++t) {
      const Eigen::Vector3i v = sphere.triangles.col(t);
      Vector9d g;
      Matrix9d h;
      volume += triangle_signed_volume(q.segment<3>(3 * v[0]), q.segment<3>(3 * v[1]), q.segment<3>(3 * v[2]), &g, &h);
      for (int a = 0; a < 3; ++a) {
        volume_gradient.segment<3>(3 * v[a]) += g.segment<3>(3 * a);
        for (int b = 0; b < 3; ++b) volume_hessian.block<3, 3>(3 * v[a], 3 * v[b]) += h.block<3, 3>(3 * a, 3 * b);
      }
    }
    double slope, curvature;
    const double energy = pressure_energy(volume, law, &slope, &curvature);
    if (gradient) *gradient = slope * volume_gradient;
    if (hessian) *hessian = curvature * volume_gradient * volume_gradient.transpose() + slope * volume_hessian;
    return energy;
  };

  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(sphere.positions.data(), n);
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
  const double energy = evaluate(q, &gradient, &hessian);
  const auto energy_remainder = [&](double a) {
    return std::abs(evaluate(q + a * direction, nullptr, nullptr) - energy - a * gradient.dot(direction));
  };
  const auto gradient_remainder = [&](double a) {
    Eigen::VectorXd moved;
    evaluate(q + a * direction, &moved, nullptr);
    return (moved - gradient - a * hessian * direction).norm();
  };
  EXPECT_TRUE(all_near_quarter(halving_ratios(energy_remainder, 1e-3, 5)));
  EXPECT_TRUE(all_near_quarter(halving_ratios(gradient_remainder, 1e-3, 5)));
}

}  // namespace
}  // namespace weft
