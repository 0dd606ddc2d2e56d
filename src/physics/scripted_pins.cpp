#include "physics/scripted_pins.hpp"

namespace weft {

Vec3 scripted_pin_position(const PinScript& script, int k, double t) {
  const Eigen::AngleAxisd rotation(script.angular_velocity * t, script.axis);
  return script.center + script.velocity * t + rotation * (script.start_positions.col(k) - script.center);
}

void drive_scripted_pins(const std::vector<PinScript>& scripts, double t, double h, Positions& x, Positions& v) {
  for (const PinScript& script : scripts) {
    for (size_t k = 0; k < script.vertices.size(); ++k) {
      const int vertex = script.vertices[k];
      v.col(vertex) = (scripted_pin_position(script, static_cast<int>(k), t + h) - x.col(vertex)) / h;
    }
  }
}

void place_scripted_pins(const std::vector<PinScript>& scripts, double t, Positions& x) {
  for (const PinScript& script : scripts) {
    for (size_t k = 0; k < script.vertices.size(); ++k) {
      x.col(script.vertices[k]) = scripted_pin_position(script, static_cast<int>(k), t);
    }
  }
}

}  // namespace weft
