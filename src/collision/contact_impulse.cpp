#include "collision/contact_impulse.hpp"

namespace weft {

ContactStencil vertex_face_stencil(const CollisionStep& step, int vertex, int triangle,
                                   const Vec3& barycentric, const Vec3& normal) {
  const auto corners = step.triangles.col(triangle);
  return {{vertex, corners[0], corners[1], corners[2]},
          {1.0, -barycentric[0], -barycentric[1], -barycentric[2]},
          normal};
}

ContactStencil edge_edge_stencil(const CollisionStep& step, int edge_a, int edge_b, double s, double t,
                                 const Vec3& normal) {
  return {{step.edges(0, edge_a), step.edges(1, edge_a), step.edges(0, edge_b), step.edges(1, edge_b)},
          {1.0 - s, s, -(1.0 - t), -t},
          normal};
}

bool shares_vertex(const CollisionStep& step, const VertexFacePair& pair) {
  const auto corners = step.triangles.col(pair.triangle);
  return corners[0] == pair.vertex || corners[1] == pair.vertex || corners[2] == pair.vertex;
}

bool shares_vertex(const CollisionStep& step, const EdgeEdgePair& pair) {
  const auto a = step.edges.col(pair.edge_a);
  const auto b = step.edges.col(pair.edge_b);
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

double inverse_effective_mass(const CollisionStep& step, const ContactStencil& stencil) {
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += stencil.weights[k] * stencil.weights[k] * step.inverse_mass[stencil.vertices[k]];
  return sum;
}

Vec3 relative_velocity(const CollisionStep& step, const ContactStencil& stencil) {
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    const int v = stencil.vertices[k];
    sum += stencil.weights[k] * (step.x_end.col(v) - step.x_start.col(v));
  }
  return sum / step.time_step;
}

Vec3 relative_start_position(const CollisionStep& step, const ContactStencil& stencil) {
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 4; ++k) sum += stencil.weights[k] * step.x_start.col(stencil.vertices[k]);
  return sum;
}

void apply_impulse(CollisionStep& step, const ContactStencil& stencil, const Vec3& impulse) {
  for (int k = 0; k < 4; ++k) {
    const int v = stencil.vertices[k];
    const Vec3 dv = (stencil.weights[k] * step.inverse_mass[v]) * impulse;
    step.velocity.col(v) += dv;
    step.x_end.col(v) += step.time_step * dv;
  }
}

}  // namespace weft
