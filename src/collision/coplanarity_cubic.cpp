#include "collision/coplanarity_cubic.hpp"

#include <algorithm>
#include <cmath>

namespace weft {

namespace {

// |f| below this fraction of the bound (|a|+|da|)(|b|+|db|)(|c|+|dc|) on |f| is round-off:
// evaluating f costs a few ulps of that bound, this leaves three orders of magnitude to spare.
constexpr double relative_tolerance = 1e-12;

// Bisection halvings: 2^-52 of the unit interval reaches double resolution near t = 1.
constexpr int bisection_steps = 52;

double derivative(const std::array<double, 4>& c, double t) {
  return c[1] + t * (2.0 * c[2] + t * 3.0 * c[3]);
}

// Sign-based bisection of g on [lo, hi] with g(lo) and g(hi) of opposite (or zero) sign; returns
// the end of the final bracket on the side of `keep_low` (conservative for the caller).
template <class G>
double bisect(const G& g, double lo, double hi, bool keep_low) {
  const bool low_negative = g(lo) < 0.0;
  for (int k = 0; k < bisection_steps && hi - lo > 0.0; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if ((g(mid) < 0.0) == low_negative) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return keep_low ? lo : hi;
}

// Appends to `breaks` the times in (lo, hi) where the monotone-or-unimodal f' changes sign.
void add_derivative_roots(const std::array<double, 4>& c, double lo, double hi, std::array<double, 6>& breaks,
                          int& count) {
  const double d_lo = derivative(c, lo);
  const double d_hi = derivative(c, hi);
  if ((d_lo < 0.0) == (d_hi < 0.0) || d_lo == 0.0 || d_hi == 0.0) return;
  breaks[count++] = bisect([&](double t) { return derivative(c, t); }, lo, hi, true);
}

}  // namespace

CoplanarityCubic coplanarity_cubic(const Vec3& a, const Vec3& da, const Vec3& b, const Vec3& db,
                                   const Vec3& c, const Vec3& dc) {
  // Expand (a + t da) x (b + t db) = ab + t (da x b + a x db) + t^2 da x db, then dot c + t dc.
  const Vec3 ab = a.cross(b);
  const Vec3 mixed = da.cross(b) + a.cross(db);
  const Vec3 dadb = da.cross(db);
  CoplanarityCubic cubic;
  cubic.coefficients = {ab.dot(c), mixed.dot(c) + ab.dot(dc), dadb.dot(c) + mixed.dot(dc), dadb.dot(dc)};
  cubic.tolerance =
      relative_tolerance * (a.norm() + da.norm()) * (b.norm() + db.norm()) * (c.norm() + dc.norm());
  return cubic;
}

double evaluate(const CoplanarityCubic& cubic, double t) {
  const std::array<double, 4>& c = cubic.coefficients;
  return c[0] + t * (c[1] + t * (c[2] + t * c[3]));
}

bool may_vanish(const CoplanarityCubic& cubic) {
  // On [0, 1] f is a convex combination of its Bernstein coefficients, so if they all lie beyond
  // the tolerance on one side, so does f. The margin covers their round-off and that of
  // evaluating f (each a few ulps of sum |c_i|), so no time near_coplanar_intervals would keep is
  // dropped (test CoplanarityCubic.MayVanish...).
  const std::array<double, 4>& c = cubic.coefficients;
  const std::array<double, 4> bernstein = {c[0], c[0] + c[1] / 3.0, c[0] + (2.0 * c[1] + c[2]) / 3.0,
                                           c[0] + c[1] + c[2] + c[3]};
  const double margin =
      cubic.tolerance + 1e-14 * (std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2]) + std::abs(c[3]));
  const auto [lowest, highest] = std::minmax_element(bernstein.begin(), bernstein.end());
  return *lowest <= margin && *highest >= -margin;
}

int near_coplanar_intervals(const CoplanarityCubic& cubic, std::array<TimeInterval, 3>& intervals) {
  const std::array<double, 4>& c = cubic.coefficients;
  const double tolerance = cubic.tolerance;

  // Pieces on which f is monotone: f'' = 2 c2 + 6 c3 t is linear, so f' is monotone on each
  // side of its root; f' then changes sign at most once on each side (found by bisection).
  std::array<double, 6> breaks;
  int count = 0;
  breaks[count++] = 0.0;
  const double inflection = c[3] != 0.0 ? -c[2] / (3.0 * c[3]) : -1.0;
  if (inflection > 0.0 && inflection < 1.0) {
    add_derivative_roots(c, 0.0, inflection, breaks, count);
    // f' may vanish right at the inflection (a triple root); keep it as a break point.
    breaks[count++] = inflection;
    add_derivative_roots(c, inflection, 1.0, breaks, count);
  } else {
    add_derivative_roots(c, 0.0, 1.0, breaks, count);
  }
  breaks[count++] = 1.0;

  // On each monotone piece {|f| <= tol} is one interval: bracket its ends by bisection on
  // f + tol and f - tol, keeping the outer end of each final bracket.
  int written = 0;
  for (int k = 0; k + 1 < count; ++k) {
    const double lo = breaks[k];
    const double hi = breaks[k + 1];
    const double f_lo = evaluate(cubic, lo);
    const double f_hi = evaluate(cubic, hi);
    const double sign = f_hi >= f_lo ? 1.0 : -1.0;  // orient so that g = sign f increases
    const double g_lo = sign * f_lo;
    const double g_hi = sign * f_hi;
    if (g_hi < -tolerance || g_lo > tolerance) continue;
    const auto g_plus = [&](double t) { return sign * evaluate(cubic, t) + tolerance; };
    const auto g_minus = [&](double t) { return sign * evaluate(cubic, t) - tolerance; };
    const double begin = g_lo >= -tolerance ? lo : bisect(g_plus, lo, hi, true);
    const double end = g_hi <= tolerance ? hi : bisect(g_minus, lo, hi, false);

    // Merge with the previous interval when they touch (a double root at a break point).
    if (written > 0 && begin <= intervals[written - 1].end) {
      intervals[written - 1].end = std::max(intervals[written - 1].end, end);
    } else if (written < 3) {
      intervals[written++] = {begin, end};
    } else {
      intervals[2].end = std::max(intervals[2].end, end);
    }
  }
  return written;
}

}  // namespace weft
