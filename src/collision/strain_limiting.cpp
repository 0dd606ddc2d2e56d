#include "collision/strain_limiting.hpp"

#include <algorithm>

namespace weft {

StrainLimitResult limit_edge_strain(CollisionStep& step, const std::vector<double>& rest_length,
                                    double max_strain, int max_sweeps) {
  StrainLimitResult result;
  const int num_edges = static_cast<int>(step.edges.cols());
  const double h = step.time_step;
  for (int e = 0; e < num_edges; ++e) {
    if (!(rest_length[e] > 0.0)) continue;
    const double length = (step.x_end.col(step.edges(1, e)) - step.x_end.col(step.edges(0, e))).norm();
    result.largest_strain_before = std::max(result.largest_strain_before, length / rest_length[e] - 1.0);
  }
  // The same test as a sweep's count below: some edge is over its limit by more than the slack.
  if (!(1.0 + result.largest_strain_before > over_limit_length(1.0, max_strain))) return result;

  for (; result.sweeps < max_sweeps;) {
    ++result.sweeps;
    int corrected = 0;
    for (int e = 0; e < num_edges; ++e) {
      const double rest = rest_length[e];
      if (!(rest > 0.0)) continue;
      const int i = step.edges(0, e);
      const int j = step.edges(1, e);
      const double w_i = step.inverse_mass[i];
      const double w_j = step.inverse_mass[j];
      if (!(w_i + w_j > 0.0)) continue;
      const Vec3 d = step.x_end.col(j) - step.x_end.col(i);
      const double length = d.norm();
      const double limit = (1.0 + max_strain) * rest;
      if (!(length > limit)) continue;
      // Shorten to the limit exactly; count it when it was past the slack.
      if (length > over_limit_length(rest, max_strain)) ++corrected;
      const Vec3 shift = (length - limit) / (length * (w_i + w_j)) * d;
      step.x_end.col(i) += w_i * shift;
      step.velocity.col(i) += (w_i / h) * shift;
      step.x_end.col(j) -= w_j * shift;
      step.velocity.col(j) -= (w_j / h) * shift;
    }
    result.corrected_edges += corrected;
    if (corrected == 0) break;
  }
  return result;
}

bool edge_over_limit(const CollisionStep& step, const StrainBound& bound, int e) {
  const double rest = bound.rest_length[e];
  const int i = step.edges(0, e), j = step.edges(1, e);
  if (!(rest > 0.0) || !(step.inverse_mass[i] + step.inverse_mass[j] > 0.0)) return false;
  const double length = (step.x_end.col(j) - step.x_end.col(i)).norm();
  if (!(length > over_limit_length(rest, bound.max_strain))) return false;
  return length > (step.x_start.col(j) - step.x_start.col(i)).norm() * (1.0 + 1e-12);
}

}  // namespace weft
