#pragma once
// Taylor tests of derivatives: a remainder r(eps) that is second order in eps falls by 4 each
// time eps halves (r(eps) = |E(x + eps d) - E(x) - eps g.d| for a gradient g, or the gradient's
// remainder for a Hessian), so the ratios of successive remainders sit near 1/4.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

namespace weft::testing {

// Ratios remainder(first_step / 2^k) / remainder(first_step / 2^(k-1)) for k = 1..halvings.
template <class Remainder>
std::vector<double> halving_ratios(const Remainder& remainder, double first_step, int halvings) {
  std::vector<double> ratios;
  double previous = remainder(first_step);
  for (int k = 1; k <= halvings; ++k) {
    const double current = remainder(first_step / (1 << k));
    ratios.push_back(current / previous);
    previous = current;
  }
  return ratios;
}

// At least four ratios, each within 0.03 of 1/4.
inline ::testing::AssertionResult all_near_quarter(const std::vector<double>& ratios) {
  std::ostringstream text;
  bool ok = ratios.size() >= 4;
  for (double r : ratios) {
    text << r << " ";
    ok = ok && std::abs(r - 0.25) <= 0.03;
  }
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "remainder ratios " << text.str();
}

}  // namespace weft::testing
