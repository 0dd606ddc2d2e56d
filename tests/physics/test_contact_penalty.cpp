// Contact penalty (physics/contact_penalty.hpp): the energy's Taylor remainder against its
// gradient, the gradient's change against the Hessian (diagonal blocks in the sparse matrix plus
// the coupling product), symmetry and positivity of that Hessian, one-sidedness, and the free mask.
#include "physics/contact_penalty.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "physics/sparse_hessian.hpp"

namespace weft {
namespace {

constexpr int num_vertices = 12;

// Random contacts among the vertices, some with a corner outside the cloth (-1), all closer than
// their thickness at `x` by at least 1 mm (so small perturbations keep them active).
ContactPenalty random_penalty(const Positions& x, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss;
  ContactPenalty penalty;
  for (int c = 0; c < 8; ++c) {
    PenaltyContact contact;
    // Four distinct vertices.
    std::vector<int> pool(num_vertices);
    for (int v = 0; v < num_vertices; ++v) pool[v] = v;
    std::shuffle(pool.begin(), pool.end(), random);
    const double s = unit(random), t = unit(random);
    contact.weights = {1.0 - s, s, -(1.0 - t), -t};
    for (int k = 0; k < 4; ++k) contact.vertices[k] = pool[k];
    if (c % 3 == 0) contact.vertices[3] = -1;  // a corner on another mesh
    contact.normal = Vec3(gauss(random), gauss(random), gauss(random)).normalized();
    contact.thickness = 0.005;
    contact.stiffness = 2500.0;
    double gap = 0.0;
    for (int k = 0; k < 4; ++k) {
      if (contact.vertices[k] >= 0) gap += contact.weights[k] * contact.normal.dot(x.col(contact.vertices[k]));
    }
    // Choose the offset so that g = thickness - (2 .. 4 mm).
    contact.offset = contact.thickness - (0.002 + 0.002 * unit(random)) - gap;
    penalty.contacts.push_back(contact);
  }
  return penalty;
}

// The penalty's full Hessian times p: diagonal blocks from the sparse matrix, coupling on top.
Eigen::VectorXd hessian_times(const ContactPenalty& penalty, const Positions& x, const Eigen::VectorXd& free,
                              const Eigen::VectorXd& p) {
  SparseHessian hessian;
  hessian.begin_pattern(num_vertices);
  hessian.finish_pattern();
  hessian.set_zero();
  penalty.evaluate(x, nullptr, &hessian);
  Eigen::VectorXd y(3 * num_vertices);
  hessian.multiply(p, y);
  penalty.add_coupling_product(x, free, p, y);
  return y;
}

Eigen::VectorXd flat(const Positions& x) { return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()); }

TEST(ContactPenalty, EnergyTaylorRemainderFallsWithOrderTwo) {
  std::mt19937 random(7);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 5; ++trial) {
    Positions x = Positions::NullaryExpr(3, num_vertices, [&] { return 0.1 * gauss(random); });
    const ContactPenalty penalty = random_penalty(x, random);
    Positions gradient = Positions::Zero(3, num_vertices);
    const double energy = penalty.evaluate(x, &gradient, nullptr);
    ASSERT_GT(energy, 0.0);
    const Positions direction = Positions::NullaryExpr(3, num_vertices, [&] { return gauss(random); });
    std::vector<double> remainders;
    for (int k = 0; k < 6; ++k) {
      const double step = 1e-4 / (1 << k);
      const Positions moved = x + step * direction;
      remainders.push_back(std::abs(penalty.evaluate(moved, nullptr, nullptr) - energy -
                                    step * flat(gradient).dot(flat(direction))));
    }
    for (size_t k = 1; k < remainders.size(); ++k) {
      EXPECT_NEAR(remainders[k] / remainders[k - 1], 0.25, 0.03) << "trial " << trial << ", halving " << k;
    }
  }
}

TEST(ContactPenalty, GradientChangesByTheHessianWhichIsSymmetricAndPositive) {
  std::mt19937 random(11);
  std::normal_distribution<double> gauss;
  const Eigen::VectorXd free = Eigen::VectorXd::Ones(3 * num_vertices);
  for (int trial = 0; trial < 5; ++trial) {
    Positions x = Positions::NullaryExpr(3, num_vertices, [&] { return 0.1 * gauss(random); });
    const ContactPenalty penalty = random_penalty(x, random);
    Positions gradient = Positions::Zero(3, num_vertices);
    penalty.evaluate(x, &gradient, nullptr);
    const Positions direction = Positions::NullaryExpr(3, num_vertices, [&] { return gauss(random); });
    // Within the active set the energy is quadratic: the gradient changes exactly by H d.
    const double step = 1e-5;
    Positions moved_gradient = Positions::Zero(3, num_vertices);
    penalty.evaluate(x + step * direction, &moved_gradient, nullptr);
    const Eigen::VectorXd change = flat(moved_gradient) - flat(gradient);
    const Eigen::VectorXd predicted = step * hessian_times(penalty, x, free, flat(direction));
    EXPECT_LT((change - predicted).norm(), 1e-9 * predicted.norm()) << "trial " << trial;

    const Eigen::VectorXd u = Eigen::VectorXd::NullaryExpr(3 * num_vertices, [&] { return gauss(random); });
    const Eigen::VectorXd v = Eigen::VectorXd::NullaryExpr(3 * num_vertices, [&] { return gauss(random); });
    const double uhv = u.dot(hessian_times(penalty, x, free, v));
    EXPECT_NEAR(uhv, v.dot(hessian_times(penalty, x, free, u)), 1e-10 * std::abs(uhv));
    EXPECT_GE(u.dot(hessian_times(penalty, x, free, u)), 0.0);
  }
}

TEST(ContactPenalty, ActsOnlyWhileCloserThanTheThickness) {
  Positions x = Positions::Zero(3, num_vertices);
  x.col(0) = Vec3(0.0, 0.004, 0.0);  // a vertex 4 mm above a point held at the origin
  ContactPenalty penalty;
  penalty.contacts.push_back({{0, -1, -1, -1}, {1.0, -1.0, 0.0, 0.0}, Vec3::UnitY(), 0.0, 0.005, 1000.0});
  Positions gradient = Positions::Zero(3, num_vertices);
  EXPECT_NEAR(penalty.evaluate(x, &gradient, nullptr), 0.5 * 1000.0 * 0.001 * 0.001, 1e-15);
  EXPECT_NEAR(gradient(1, 0), -1000.0 * 0.001, 1e-12);  // pushes the vertex up
  x(1, 0) = 0.006;
  gradient.setZero();
  EXPECT_EQ(penalty.evaluate(x, &gradient, nullptr), 0.0);
  EXPECT_TRUE(gradient.isZero(0.0));
  penalty.contacts.clear();  // off
  x(1, 0) = 0.001;
  EXPECT_EQ(penalty.evaluate(x, &gradient, nullptr), 0.0);
}

TEST(ContactPenalty, CouplingSkipsFixedVertices) {
  Positions x = Positions::Zero(3, num_vertices);
  ContactPenalty penalty;
  penalty.contacts.push_back({{0, 1, 2, 3}, {1.0, 0.0, -0.5, -0.5}, Vec3::UnitY(), 0.0, 0.005, 1000.0});
  Eigen::VectorXd free = Eigen::VectorXd::Ones(3 * num_vertices);
  const Eigen::VectorXd p = Eigen::VectorXd::Ones(3 * num_vertices);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * num_vertices);
  penalty.add_coupling_product(x, free, p, y);
  // Row of vertex 0: kappa w_0 (w_2 + w_3) (n . p) n = 1000 * 1 * (-1) * 1 along y.
  EXPECT_NEAR(y[1], -1000.0, 1e-9);
  free.segment<3>(0).setZero();  // vertex 0 pinned
  y.setZero();
  penalty.add_coupling_product(x, free, p, y);
  EXPECT_TRUE(y.segment<3>(0).isZero(0.0));
  EXPECT_NEAR(y[3 * 2 + 1], 250.0, 1e-9);  // kappa w_2 (w_1 + w_3): 1000 * -0.5 * (0 - 0.5)
}

}  // namespace
}  // namespace weft
