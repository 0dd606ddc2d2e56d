#pragma once
// Symplectic (semi-implicit) Euler: v += h M^-1 f(x, v); x += h v. Pinned vertices
// (inverse mass 0) keep their velocity, which is zero for fixed pins.
#include "physics/cloth.hpp"

namespace weft {

void symplectic_euler_step(const ClothModel& model, ClothState& state, const Vec3& gravity, double h);
inline void symplectic_euler_step(Cloth& cloth, const Vec3& gravity, double h) {
  symplectic_euler_step(cloth.model, cloth.state, gravity, h);
}

}  // namespace weft
