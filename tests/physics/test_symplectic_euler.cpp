// Symplectic Euler on one spring of the mass-spring model: a mass on it oscillates with the
// analytic period 2 pi sqrt(m/k), and free fall matches x0 + v0 t + g t^2/2 to the
// integrator's order.
#include "physics/symplectic_euler.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace weft {
namespace {

// Vertex 0 pinned at the origin, vertex 1 of mass m on a spring of rest length 1 along x.
Cloth spring_oscillator(double mass, double stiffness, double stretch) {
  ClothModel model;
  model.rest_positions.resize(3, 2);
  model.rest_positions.col(0) << 0, 0, 0;
  model.rest_positions.col(1) << 1, 0, 0;
  model.mass = Eigen::Vector2d(1.0, mass);
  model.inverse_mass = Eigen::Vector2d(0.0, 1.0 / mass);
  model.springs.vertices.resize(2, 1);
  model.springs.vertices.col(0) << 0, 1;
  model.springs.rest_length.setConstant(1, 1.0);
  model.springs.stiffness.setConstant(1, stiffness);
  model.springs.damping.setConstant(1, 0.0);
  model.springs.kind_begin[1] = model.springs.kind_begin[2] = model.springs.kind_begin[3] = 1;
  Cloth cloth = make_cloth(std::move(model));
  cloth.state.x(0, 1) += stretch;
  return cloth;
}

TEST(SymplecticEuler, SpringMassPeriodMatchesAnalytic) {
  const double mass = 0.3, stiffness = 50.0;
  const double period = 2.0 * M_PI * std::sqrt(mass / stiffness);
  const double h = period / 2000.0;
  Cloth cloth = spring_oscillator(mass, stiffness, 0.1);
  // Upward zero crossings of the displacement, interpolated linearly inside the step.
  std::vector<double> crossings;
  double previous = cloth.state.x(0, 1) - 1.0;
  for (int step = 1; step <= 20000 && crossings.size() < 4; ++step) {
    symplectic_euler_step(cloth, Vec3::Zero(), h);
    const double current = cloth.state.x(0, 1) - 1.0;
    if (previous < 0.0 && current >= 0.0) {
      crossings.push_back((step - 1 + previous / (previous - current)) * h);
    }
    previous = current;
  }
  ASSERT_EQ(crossings.size(), 4u);
  const double measured = (crossings[3] - crossings[0]) / 3.0;
  EXPECT_NEAR(measured / period, 1.0, 1e-4);
  // The pinned end never moves.
  EXPECT_EQ(cloth.state.x.col(0), Vec3::Zero());
}

TEST(SymplecticEuler, UndampedOscillatorEnergyStaysBoundedWithoutDrift) {
  const double mass = 0.3, stiffness = 50.0;
  Cloth cloth = spring_oscillator(mass, stiffness, 0.1);
  const double omega = std::sqrt(stiffness / mass);
  const int steps_per_period = 200;
  const double h = 2.0 * M_PI / omega / steps_per_period;
  const auto energy = [&] {
    return 0.5 * mass * cloth.state.v.col(1).squaredNorm() + spring_energy(cloth.model.springs, cloth.state.x);
  };
  const double initial = energy();
  double worst = 0.0, first_period_mean = 0.0, last_period_mean = 0.0;
  const int periods = 100;
  for (int step = 0; step < periods * steps_per_period; ++step) {
    symplectic_euler_step(cloth, Vec3::Zero(), h);
    const double relative = energy() / initial - 1.0;
    worst = std::max(worst, std::abs(relative));
    if (step < steps_per_period) first_period_mean += relative / steps_per_period;
    if (step >= (periods - 1) * steps_per_period) last_period_mean += relative / steps_per_period;
  }
  // Symplectic Euler conserves a modified energy: the true energy oscillates with relative
  // amplitude omega h / 2 and does not drift from period to period.
  EXPECT_LT(worst, 0.55 * omega * h);
  EXPECT_GT(worst, 0.3 * omega * h);  // the oscillation is real, so the bound above is meaningful
  EXPECT_NEAR(first_period_mean, last_period_mean, 1e-6);
}

TEST(SymplecticEuler, FreeFallConvergesWithOrderOne) {
  const Vec3 gravity(0, -9.81, 0);
  const double duration = 0.5;
  std::vector<double> errors;
  for (int steps : {50, 100, 200, 400}) {
    Cloth cloth = spring_oscillator(1.0, 0.0, 0.0);
    cloth.model.inverse_mass.setOnes();  // both vertices free, no spring force
    for (int k = 0; k < steps; ++k) symplectic_euler_step(cloth, gravity, duration / steps);
    const double exact = 0.5 * gravity.y() * duration * duration;
    errors.push_back(std::abs(cloth.state.x(1, 0) - exact));
  }
  for (size_t k = 1; k < errors.size(); ++k) {
    EXPECT_NEAR(errors[k - 1] / errors[k], 2.0, 0.05);
  }
}

}  // namespace
}  // namespace weft
