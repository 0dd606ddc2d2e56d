#include "physics/integrator.hpp"

namespace weft {

const char* to_string(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::symplectic_euler:
      return "symplectic_euler";
    case IntegratorKind::midpoint_euler_cromer:
      return "midpoint_euler_cromer";
    case IntegratorKind::explicit_midpoint:
      return "explicit_midpoint";
    case IntegratorKind::implicit_euler:
      return "implicit_euler";
    case IntegratorKind::xpbd:
      return "xpbd";
  }
  return "unknown";
}

}  // namespace weft
