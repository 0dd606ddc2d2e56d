// Membrane: energy, gradient and Hessian agree by Taylor tests in every strain regime of the
// compression split; zero energy and force at rest and under rigid motion; the analytic StVK
// energy in uniaxial stretch; a softer response in compression only; the plastic rest update.
#include "physics/membrane_stvk.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <vector>

#include "physics/psd_projection.hpp"
#include "support/taylor.hpp"

namespace weft {
namespace {

using weft::testing::all_near_quarter;
using weft::testing::halving_ratios;

struct Triangle {
  Vec3 x[3];
};

Vector9d stack(const Triangle& t) {
  Vector9d q;
  q << t.x[0], t.x[1], t.x[2];
  return q;
}

Triangle unstack(const Vector9d& q) { return Triangle{{q.segment<3>(0), q.segment<3>(3), q.segment<3>(6)}}; }

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

Eigen::Matrix2d rotation_2d(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

// A rest triangle (2D points p, placed in 3D by a random rigid motion) and a deformed copy whose
// in-plane deformation has principal stretches s1, s2 (so principal Green strains (s^2 - 1)/2).
struct Sample {
  Triangle rest;
  Triangle deformed;
};

Sample random_sample(std::mt19937& rng, double s1, double s2) {
  std::uniform_real_distribution<double> noise(-0.2, 0.2);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * pi);
  const Eigen::Vector2d p[3] = {{noise(rng), noise(rng)}, {1.0 + noise(rng), noise(rng)},
                                {0.3 + noise(rng), 0.9 + noise(rng)}};
  const Eigen::Matrix2d g = rotation_2d(angle(rng)) * Eigen::Vector2d(s1, s2).asDiagonal() * rotation_2d(angle(rng));
  const Mat3 rest_rotation = random_rotation(rng);
  const Mat3 rotation = random_rotation(rng);
  const Vec3 rest_shift(noise(rng), noise(rng), noise(rng));
  const Vec3 shift(noise(rng), noise(rng), noise(rng));
  Sample s;
  for (int i = 0; i < 3; ++i) {
    s.rest.x[i] = rest_rotation * Vec3(p[i].x(), p[i].y(), 0.0) + rest_shift;
    const Eigen::Vector2d q = g * p[i];
    s.deformed.x[i] = rotation * Vec3(q.x(), q.y(), 0.0) + shift;
  }
  return s;
}

MembraneRest rest_of(const Triangle& t) { return membrane_rest(t.x[0], t.x[1], t.x[2]); }

double energy_of(const Vector9d& q, const MembraneRest& rest, const MembraneMaterial& material,
                 Vector9d* gradient = nullptr, Matrix9d* hessian = nullptr) {
  const Triangle t = unstack(q);
  return membrane_energy(t.x[0], t.x[1], t.x[2], rest, material, gradient, hessian);
}

// Stretch ranges of the three regimes of the compression split.
enum class Regime { stretched, compressed, mixed, flattened, flattened_both };

void stretch_pair(Regime regime, std::mt19937& rng, double& s1, double& s2) {
  std::uniform_real_distribution<double> stretch(1.15, 1.4);
  std::uniform_real_distribution<double> squeeze(0.6, 0.85);
  std::uniform_real_distribution<double> flatten(0.2, 0.4);  // past a min_stretch of 0.5
  switch (regime) {
    case Regime::flattened:
      do {
        s1 = stretch(rng), s2 = flatten(rng);
      } while (std::abs(0.5 * (s1 * s1 + s2 * s2) - 1.0) < 0.05);
      break;
    case Regime::flattened_both:
      s1 = flatten(rng), s2 = flatten(rng);
      break;
    case Regime::stretched:
      s1 = stretch(rng), s2 = stretch(rng);
      break;
    case Regime::compressed:
      s1 = squeeze(rng), s2 = squeeze(rng);
      break;
    case Regime::mixed:
      // Keep tr(E) away from zero too: a Taylor step must not cross a kink of the tangent.
      do {
        s1 = stretch(rng), s2 = squeeze(rng);
      } while (std::abs(0.5 * (s1 * s1 + s2 * s2) - 1.0) < 0.05);
      break;
  }
}

void check_derivatives(Regime regime, double compression_factor, unsigned seed, double min_stretch = 0.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  MembraneMaterial material;
  material.compression_factor = compression_factor;
  material.min_stretch = min_stretch;
  for (int trial = 0; trial < 5; ++trial) {
    double s1, s2;
    stretch_pair(regime, rng, s1, s2);
    const Sample sample = random_sample(rng, s1, s2);
    const MembraneRest rest = rest_of(sample.rest);
    const Vector9d q = stack(sample.deformed);
    Vector9d direction;
    for (int i = 0; i < 9; ++i) direction[i] = normal(rng);
    Vector9d gradient;
    Matrix9d hessian;
    const double energy = energy_of(q, rest, material, &gradient, &hessian);

    const auto energy_remainder = [&](double a) {
      return std::abs(energy_of(q + a * direction, rest, material) - energy - a * gradient.dot(direction));
    };
    const auto gradient_remainder = [&](double a) {
      Vector9d moved;
      energy_of(q + a * direction, rest, material, &moved);
      return (moved - gradient - a * hessian * direction).norm();
    };
    EXPECT_TRUE(all_near_quarter(halving_ratios(energy_remainder, 1e-3, 5))) << "trial " << trial;
    EXPECT_TRUE(all_near_quarter(halving_ratios(gradient_remainder, 1e-3, 5))) << "trial " << trial;
    EXPECT_LE((hessian - hessian.transpose()).norm(), 1e-10 * hessian.norm());

    Matrix9d projected = hessian;
    project_to_psd(projected);
    const Eigen::SelfAdjointEigenSolver<Matrix9d> eigen(projected);
    // Against the unprojected Hessian's scale: a triangle flattened both ways can have almost no
    // positive curvature left, and the projection is then round-off.
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * hessian.norm());
  }
}

TEST(MembraneStvk, DerivativesTaylorTestPlainStvk) {
  check_derivatives(Regime::stretched, 1.0, 1);
  check_derivatives(Regime::compressed, 1.0, 2);
  check_derivatives(Regime::mixed, 1.0, 3);
}

TEST(MembraneStvk, DerivativesTaylorTestSoftCompressionInEveryRegime) {
  check_derivatives(Regime::stretched, 0.1, 4);
  check_derivatives(Regime::compressed, 0.1, 5);
  check_derivatives(Regime::mixed, 0.1, 6);
  check_derivatives(Regime::mixed, 0.5, 7);
}

// min_stretch 0.5: principal stretches in [0.2, 0.4] are past its Green strain -0.375 (and the
// compressed regime's [0.6, 0.85] short of it).
TEST(MembraneStvk, DerivativesTaylorTestWithASmallestStretch) {
  check_derivatives(Regime::flattened, 0.01, 8, 0.5);
  check_derivatives(Regime::flattened_both, 0.01, 9, 0.5);
  check_derivatives(Regime::mixed, 0.01, 10, 0.5);
  check_derivatives(Regime::compressed, 0.01, 11, 0.5);
}

// Above the smallest stretch the energy is the soft one exactly; flattening past it costs the
// full stiffness on the excess: mu (1 - c)(e - e0)^2 more, e = (s^2 - 1)/2, e0 = (s0^2 - 1)/2,
// for a triangle squeezed along one rest axis to stretch s (the other kept at 1).
TEST(MembraneStvk, ASmallestStretchResistsFlatteningAtFullStiffness) {
  MembraneMaterial soft;
  soft.young_modulus = 1e5;
  soft.poisson_ratio = 0.3;
  soft.compression_factor = 0.01;
  MembraneMaterial floored = soft;
  floored.min_stretch = 0.5;
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const MembraneRest rest = membrane_rest(a, b, c);
  const double mu = soft.young_modulus / (2.0 * (1.0 + soft.poisson_ratio));
  const double volume = rest.area * soft.thickness;
  const double e0 = 0.5 * (0.25 - 1.0);
  for (const double stretch : {0.9, 0.6, 0.51, 0.45, 0.3, 0.1}) {
    const Vec3 squeezed(0, stretch, 0);
    const double soft_energy = membrane_energy(a, b, squeezed, rest, soft, nullptr, nullptr);
    const double floored_energy = membrane_energy(a, b, squeezed, rest, floored, nullptr, nullptr);
    const double e = 0.5 * (stretch * stretch - 1.0);
    const double extra = e < e0 ? mu * (1.0 - soft.compression_factor) * (e - e0) * (e - e0) * volume : 0.0;
    EXPECT_NEAR(floored_energy - soft_energy, extra, 1e-12 * (1.0 + floored_energy)) << "stretch " << stretch;
    if (stretch < 0.5) {
      EXPECT_GT(floored_energy, soft_energy) << "stretch " << stretch;
    }
  }
}

// The projected Hessian (psd = true) is positive semi-definite in every regime, equals the exact
// one where the triangle is stretched both ways (nothing to clamp), and only adds curvature
// elsewhere (it drops the compressive stress's negative geometric part, all of it when the
// triangle is squeezed both ways), with the same energy and gradient.
TEST(MembraneStvk, ProjectedHessianIsPsdAndOnlyAddsCurvature) {
  std::mt19937 rng(11);
  MembraneMaterial material;
  material.compression_factor = 0.1;
  for (const Regime regime : {Regime::stretched, Regime::compressed, Regime::mixed}) {
    for (int trial = 0; trial < 5; ++trial) {
      double s1, s2;
      stretch_pair(regime, rng, s1, s2);
      const Sample sample = random_sample(rng, s1, s2);
      const MembraneRest rest = rest_of(sample.rest);
      const Triangle& t = sample.deformed;
      Vector9d gradient, projected_gradient;
      Matrix9d hessian, projected;
      const double energy =
          membrane_energy(t.x[0], t.x[1], t.x[2], rest, material, &gradient, &hessian, false);
      const double projected_energy =
          membrane_energy(t.x[0], t.x[1], t.x[2], rest, material, &projected_gradient, &projected, true);
      EXPECT_EQ(energy, projected_energy);
      EXPECT_LE((gradient - projected_gradient).norm(), 1e-14 * gradient.norm());
      const double scale = hessian.norm();
      const Eigen::SelfAdjointEigenSolver<Matrix9d> eigen(0.5 * (projected + projected.transpose()));
      EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * scale) << "trial " << trial;
      const Matrix9d added = projected - hessian;
      if (regime == Regime::stretched) {
        EXPECT_LE(added.norm(), 1e-12 * scale) << "trial " << trial;
      } else {
        // Squeezed both ways the stress is compressive both ways: its whole geometric part goes.
        if (regime == Regime::compressed) {
          EXPECT_GT(added.norm(), 1e-6 * scale) << "trial " << trial;
        }
        const Eigen::SelfAdjointEigenSolver<Matrix9d> change(0.5 * (added + added.transpose()));
        EXPECT_GE(change.eigenvalues().minCoeff(), -1e-10 * scale) << "trial " << trial;
      }
    }
  }
}

TEST(MembraneStvk, NoEnergyOrForceAtRestOrUnderRigidMotion) {
  std::mt19937 rng(11);
  MembraneMaterial material;
  material.compression_factor = 0.2;
  for (int trial = 0; trial < 5; ++trial) {
    const Sample sample = random_sample(rng, 1.0, 1.0);  // deformed = rigid motion of rest
    const MembraneRest rest = rest_of(sample.rest);
    const double force_scale = material.young_modulus * material.thickness * std::sqrt(rest.area);
    Vector9d gradient;
    Matrix9d hessian;
    EXPECT_NEAR(energy_of(stack(sample.rest), rest, material, &gradient, &hessian), 0.0, 1e-20);
    EXPECT_LE(gradient.norm(), 1e-12 * force_scale);
    EXPECT_NEAR(energy_of(stack(sample.deformed), rest, material, &gradient, &hessian), 0.0, 1e-20);
    EXPECT_LE(gradient.norm(), 1e-12 * force_scale);
    EXPECT_LE(green_strain(sample.deformed.x[0], sample.deformed.x[1], sample.deformed.x[2], rest).norm(), 1e-14);
  }
}

TEST(MembraneStvk, UniaxialStretchGivesAnalyticEnergy) {
  // Rest triangle in the XY plane; x -> s x with no lateral contraction: E = diag(eps, 0) with
  // eps = (s^2 - 1)/2, psi = (mu + lambda/2) eps^2, times c in compression.
  MembraneMaterial material;
  material.compression_factor = 0.25;
  const double mu = material.young_modulus / (2.0 * (1.0 + material.poisson_ratio));
  const double lambda =
      material.young_modulus * material.poisson_ratio / (1.0 - material.poisson_ratio * material.poisson_ratio);
  const Vec3 x0(0.1, -0.2, 0.0), x1(1.3, 0.1, 0.0), x2(0.4, 0.8, 0.0);
  const MembraneRest rest = membrane_rest(x0, x1, x2);
  EXPECT_NEAR(rest.area, 0.5 * (x1 - x0).cross(x2 - x0).norm(), 1e-15);
  for (double s : {1.2, 0.8}) {
    const Mat3 stretch = Vec3(s, 1.0, 1.0).asDiagonal();
    const double eps = 0.5 * (s * s - 1.0);
    const double expected = rest.area * material.thickness * (mu + 0.5 * lambda) * eps * eps *
                            (s < 1.0 ? material.compression_factor : 1.0);
    const double energy = membrane_energy(stretch * x0, stretch * x1, stretch * x2, rest, material, nullptr, nullptr);
    EXPECT_NEAR(energy, expected, 1e-12 * expected) << "stretch " << s;
  }
}

TEST(MembraneStvk, UnitCompressionFactorIsPlainStvk) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> stretch(0.6, 1.4);
  const MembraneMaterial material;
  const double mu = material.young_modulus / (2.0 * (1.0 + material.poisson_ratio));
  const double lambda =
      material.young_modulus * material.poisson_ratio / (1.0 - material.poisson_ratio * material.poisson_ratio);
  for (int trial = 0; trial < 20; ++trial) {
    const Sample sample = random_sample(rng, stretch(rng), stretch(rng));
    const MembraneRest rest = rest_of(sample.rest);
    const Triangle& t = sample.deformed;
    const Eigen::Matrix2d e = green_strain(t.x[0], t.x[1], t.x[2], rest);
    const double expected =
        rest.area * material.thickness * (mu * (e * e).trace() + 0.5 * lambda * e.trace() * e.trace());
    EXPECT_NEAR(energy_of(stack(t), rest, material), expected, 1e-12 * expected);
  }
}

TEST(MembraneStvk, CompressionFactorSoftensCompressionOnly) {
  std::mt19937 rng(31);
  MembraneMaterial stiff;
  MembraneMaterial soft;
  soft.compression_factor = 0.3;
  for (Regime regime : {Regime::stretched, Regime::compressed, Regime::mixed}) {
    for (int trial = 0; trial < 5; ++trial) {
      double s1, s2;
      stretch_pair(regime, rng, s1, s2);
      const Sample sample = random_sample(rng, s1, s2);
      const MembraneRest rest = rest_of(sample.rest);
      const double stiff_energy = energy_of(stack(sample.deformed), rest, stiff);
      const double soft_energy = energy_of(stack(sample.deformed), rest, soft);
      if (regime == Regime::stretched) {
        EXPECT_NEAR(soft_energy, stiff_energy, 1e-12 * stiff_energy);
      } else {
        EXPECT_LT(soft_energy, 0.95 * stiff_energy);
      }
      if (regime == Regime::compressed) {
        EXPECT_NEAR(soft_energy, 0.3 * stiff_energy, 1e-12 * stiff_energy);
      }
    }
  }
}

TEST(MembraneStvk, StressIsContinuousWhereAPrincipalStrainCrossesZero) {
  // Stretch s along a rotated axis, s through 1: the force has no jump between s = 1 -+ 1e-7.
  MembraneMaterial material;
  material.compression_factor = 0.1;
  const Vec3 x0(0.0, 0.0, 0.0), x1(1.0, 0.2, 0.0), x2(0.3, 0.9, 0.0);
  const MembraneRest rest = membrane_rest(x0, x1, x2);
  const Mat3 axes = Eigen::AngleAxisd(0.4, Vec3::UnitZ()).toRotationMatrix();
  // The other axis is stretched 10%: mixed principal strains below s = 1, both positive above.
  Vector9d below, above;
  for (double s : {1.0 - 1e-7, 1.0 + 1e-7}) {
    const Mat3 map = axes * Vec3(s, 1.1, 1.0).asDiagonal() * axes.transpose();
    membrane_energy(map * x0, map * x1, map * x2, rest, material, s < 1.0 ? &below : &above, nullptr);
  }
  EXPECT_LE((above - below).norm(), 1e-5 * above.norm());
}

// The closed form against an eigensolver, on strains of every sign and anisotropy.
TEST(MembraneStvk, LargestPrincipalStrainIsTheLargerEigenvalue) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> entry(-2.0, 2.0);
  for (int k = 0; k < 200; ++k) {
    Eigen::Matrix2d strain;
    strain(0, 0) = entry(rng);
    strain(1, 1) = k % 10 == 0 ? strain(0, 0) : entry(rng);  // some with equal diagonals
    strain(0, 1) = strain(1, 0) = k % 7 == 0 ? 0.0 : entry(rng);
    const double expected = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(strain, Eigen::EigenvaluesOnly)
                                .eigenvalues()
                                .maxCoeff();
    EXPECT_NEAR(largest_principal_strain(strain), expected, 1e-14 * (1.0 + strain.norm())) << strain;
  }
}

TEST(MembraneStvk, ZeroAreaRestThrows) {
  EXPECT_THROW(membrane_rest(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)), std::invalid_argument);
  EXPECT_THROW(membrane_rest(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)), std::invalid_argument);
}

// Largest and smallest principal Green strain.
Eigen::Vector2d principal_strains(const Triangle& t, const MembraneRest& rest) {
  const Eigen::Matrix2d e = green_strain(t.x[0], t.x[1], t.x[2], rest);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(e);
  return Eigen::Vector2d(eigen.eigenvalues()(1), eigen.eigenvalues()(0));
}

TEST(MembraneStvk, PlasticYieldShrinksTheExcessStrainByTheFlowFraction) {
  std::mt19937 rng(41);
  const double yield = 0.1;
  const double flow = 0.4;
  for (auto [s1, s2] : {std::pair{1.5, 1.02}, std::pair{0.7, 1.05}, std::pair{1.3, 0.8}}) {
    const Sample sample = random_sample(rng, s1, s2);
    MembraneRest rest = rest_of(sample.rest);
    const Eigen::Vector2d before = principal_strains(sample.deformed, rest);
    const Triangle& t = sample.deformed;
    ASSERT_TRUE(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, yield, flow));
    const Eigen::Vector2d after = principal_strains(t, rest);
    for (int i = 0; i < 2; ++i) {
      const double excess = std::abs(before[i]) - yield;
      const double expected = excess > 0.0 ? std::copysign(yield + (1.0 - flow) * excess, before[i]) : before[i];
      EXPECT_NEAR(after[i], expected, 1e-12) << "stretches " << s1 << ", " << s2;
    }
    // The rest area stays the area of the rest edges that dm_inverse describes.
    EXPECT_NEAR(rest.area, 0.5 / std::abs(rest.dm_inverse.determinant()), 1e-12 * rest.area);
  }
}

TEST(MembraneStvk, PlasticYieldBelowTheLimitOrWithoutFlowChangesNothing) {
  std::mt19937 rng(43);
  const Sample sample = random_sample(rng, 1.1, 0.95);  // strains 0.105 and -0.049
  const Triangle& t = sample.deformed;
  MembraneRest rest = rest_of(sample.rest);
  const MembraneRest original = rest;
  EXPECT_FALSE(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, 0.2, 0.5));
  EXPECT_FALSE(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, 0.05, 0.0));
  EXPECT_EQ(rest.dm_inverse, original.dm_inverse);
  EXPECT_EQ(rest.area, original.area);
  // Full flow with zero yield adopts the current shape: no energy left.
  EXPECT_TRUE(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, 0.0, 1.0));
  EXPECT_NEAR(energy_of(stack(t), rest, MembraneMaterial{}), 0.0, 1e-20);
  EXPECT_THROW(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, -1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(apply_plastic_yield(t.x[0], t.x[1], t.x[2], rest, 0.1, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace weft
