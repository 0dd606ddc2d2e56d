#pragma once
// Dragging a cloth vertex with the mouse: a damped spring from the grabbed vertex to the cursor's
// point in the world, applied as the World's external force. No OpenGL and no ImGui.
#include "sim/world.hpp"

namespace weft {

class VertexDrag {
 public:
  // Spring per unit vertex mass: stiffness m w^2, damping 2 zeta m w (critically damped for zeta 1).
  double angular_frequency = 25.0;  // rad/s
  double damping_ratio = 1.0;

  // Grabs vertex `vertex` of cloth `cloth`; the spring pulls it towards `target`.
  void begin(int cloth, int vertex, const Vec3& target);
  void move_to(const Vec3& target) { target_ = target; }
  // Lets go and clears the force it put on the world.
  void end(World& world);

  // Writes the spring force into world.external_force(cloth) (call before each step). Does
  // nothing when not dragging or when the cloth no longer exists (after a reload).
  void apply(World& world) const;

  bool active() const { return cloth_ >= 0; }
  int cloth() const { return cloth_; }
  int vertex() const { return vertex_; }
  const Vec3& target() const { return target_; }

 private:
  int cloth_ = -1;
  int vertex_ = -1;
  Vec3 target_ = Vec3::Zero();
};

}  // namespace weft
