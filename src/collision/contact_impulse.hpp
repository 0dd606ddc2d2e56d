#pragma once
// A contact as four weighted vertices: the relative velocity at the contact is
// sum_k weight_k v_k (vertex-face: 1, -w_a, -w_b, -w_c; edge-edge: 1 - s, s, -(1 - t), -t), and an
// impulse J on it changes v_k by weight_k inverse_mass_k J (BFA 2002 section 7.1, with unequal
// masses). The weights sum to zero, so these impulses conserve linear momentum.
#include <array>

#include "collision/collision_step.hpp"
#include "collision/contact_pairs.hpp"
#include "collision/contact_record.hpp"

namespace weft {

struct ContactStencil {
  std::array<int, 4> vertices;
  std::array<double, 4> weights;
  Vec3 normal;  // unit; the relative velocity's component along it is the approach speed (< 0)
};

ContactStencil vertex_face_stencil(const CollisionStep& step, int vertex, int triangle,
                                   const Vec3& barycentric, const Vec3& normal);
ContactStencil edge_edge_stencil(const CollisionStep& step, int edge_a, int edge_b, double s, double t,
                                 const Vec3& normal);

// Whether the two primitives share a vertex (such pairs are never in contact).
bool shares_vertex(const CollisionStep& step, const VertexFacePair& pair);
bool shares_vertex(const CollisionStep& step, const EdgeEdgePair& pair);

// sum_k weight_k^2 inverse_mass_k: the relative velocity changes by this times the impulse.
double inverse_effective_mass(const CollisionStep& step, const ContactStencil& stencil);

// Relative velocity of the stencil from the step's average velocities (x_end - x_start)/h.
Vec3 relative_velocity(const CollisionStep& step, const ContactStencil& stencil);

// Relative position of the stencil at the start of the step.
Vec3 relative_start_position(const CollisionStep& step, const ContactStencil& stencil);

// Applies `impulse` (a vector, kg m/s) to the stencil: x_end moves by h dv_k and velocity by dv_k.
void apply_impulse(CollisionStep& step, const ContactStencil& stencil, const Vec3& impulse);

}  // namespace weft
