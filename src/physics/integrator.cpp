#include "physics/integrator.hpp"

namespace weft {

const char* to_string(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::symplectic_euler:
      return "symplectic_euler";
  }
  return "unknown";
}

bool integrator_from_string(const std::string& name, IntegratorKind& kind) {
  if (name == "symplectic_euler") {
    kind = IntegratorKind::symplectic_euler;
    return true;
  }
  return false;
}

}  // namespace weft
