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

bool integrator_from_string(const std::string& name, IntegratorKind& kind) {
  for (IntegratorKind candidate :
       {IntegratorKind::symplectic_euler, IntegratorKind::midpoint_euler_cromer, IntegratorKind::explicit_midpoint,
        IntegratorKind::implicit_euler,
        IntegratorKind::xpbd}) {
    if (name == to_string(candidate)) {
      kind = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace weft
