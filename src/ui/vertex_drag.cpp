#include "ui/vertex_drag.hpp"

namespace weft {

namespace {

bool valid(const World& world, int cloth, int vertex) {
  return cloth >= 0 && cloth < static_cast<int>(world.cloths().size()) && vertex >= 0 &&
         vertex < world.cloths()[static_cast<size_t>(cloth)].num_vertices();
}

}  // namespace

void VertexDrag::begin(int cloth, int vertex, const Vec3& target) {
  cloth_ = cloth;
  vertex_ = vertex;
  target_ = target;
}

void VertexDrag::end(World& world) {
  if (valid(world, cloth_, vertex_)) world.external_force(cloth_).col(vertex_).setZero();
  cloth_ = vertex_ = -1;
}

void VertexDrag::apply(World& world) const {
  if (!valid(world, cloth_, vertex_)) return;
  const Cloth& cloth = world.cloths()[static_cast<size_t>(cloth_)];
  const double mass = cloth.model.mass[vertex_];
  const double stiffness = mass * angular_frequency * angular_frequency;
  const double damping = 2.0 * damping_ratio * mass * angular_frequency;
  world.external_force(cloth_).col(vertex_) =
      stiffness * (target_ - cloth.state.x.col(vertex_)) - damping * cloth.state.v.col(vertex_);
}

}  // namespace weft
