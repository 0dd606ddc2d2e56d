#include "physics/contact_barrier.hpp"

#include <cmath>

namespace weft {

BarrierValue log_barrier(double d, double dhat) {
  BarrierValue b;
  if (!(d < dhat)) return b;
  const double gap = d - dhat;  // < 0
  const double log_ratio = std::log(d / dhat);
  b.value = -gap * gap * log_ratio;
  b.first = -2.0 * gap * log_ratio - gap * gap / d;
  b.second = -2.0 * log_ratio - 4.0 * gap / d + gap * gap / (d * d);
  return b;
}

FrictionValue smoothed_friction(double y, double eps) {
  FrictionValue f;
  if (y >= eps) {
    f.value = y;
    f.first = 1.0;
    f.ratio = 1.0 / y;
    return f;
  }
  f.value = -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0;
  f.first = 2.0 * y / eps - y * y / (eps * eps);
  f.ratio = 2.0 / eps - y / (eps * eps);
  f.second = 2.0 / eps - 2.0 * y / (eps * eps);
  return f;
}

}  // namespace weft
