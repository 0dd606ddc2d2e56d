#include "collision/proximity_response.hpp"

#include <algorithm>

#include "collision/contact_impulse.hpp"
#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"

namespace weft {

namespace {

// Fraction of the remaining overlap the repulsion may close in one step (BFA 2002 section 7.2).
constexpr double repulsion_overlap_fraction = 0.1;

// The normal of a pair in contact (distance ~ 0) when the gap gives none: the fallback direction
// turned against the relative velocity, so the pair separates along it.
Vec3 normal_from(const Vec3& gap, const Vec3& fallback, const Vec3& relative_velocity) {
  Vec3 normal = gap.norm() > 0.0 ? gap : fallback;
  if (!(normal.norm() > 0.0))
    normal = relative_velocity.norm() > 0.0 ? Vec3(-relative_velocity) : Vec3::UnitZ();
  normal.normalize();
  if (gap.norm() == 0.0 && normal.dot(relative_velocity) > 0.0) normal = -normal;
  return normal;
}

// Normal impulse and friction for one pair at `distance` < thickness; returns the magnitude of
// the normal impulse, the penalty's included (0 when none acted).
double respond(CollisionStep& step, const ContactStencil& stencil, double distance,
               const ResponseSettings& settings) {
  const double inverse_mass = inverse_effective_mass(step, stencil);
  if (!(inverse_mass > 0.0)) return 0.0;
  const double h = step.time_step;
  const Vec3 velocity = relative_velocity(step, stencil);
  const double normal_speed = velocity.dot(stencil.normal);
  const double overlap = settings.thickness - distance;

  // Inelastic part: cancel the approach (v_N < 0) entirely.
  const double after_inelastic = std::max(normal_speed, 0.0);
  double speed_change = after_inelastic - normal_speed;

  // Repulsion: a spring impulse h k overlap, limited so that the pair separates by no more than a
  // tenth of the overlap per step: I = min(h k d, m (0.1 d/h - v_N)) (BFA 2002 section 7.2).
  const double target_speed = repulsion_overlap_fraction * overlap / h;
  if (after_inelastic < target_speed) {
    speed_change +=
        std::min(h * settings.repulsion_stiffness * overlap * inverse_mass, target_speed - after_inelastic);
  }
  // The contact penalty inside implicit Euler already pushed the pair apart during the step, with
  // about h kappa (thickness - gap) at the gap where the solve left it; that impulse counts
  // towards the friction bound like the one above. A collider contact's penalty holds the pair
  // at its thickness or at its start gap when nearer (CollisionPhase::collider_contacts), with
  // kappa = ratio m / h^2: a velocity change of ratio (min(thickness, start gap) - gap) / h.
  const double start_gap = stencil.normal.dot(relative_start_position(step, stencil));
  const double end_gap = start_gap + h * normal_speed;
  const double penalty_change =
      h * settings.penalty_stiffness * std::max(settings.thickness - end_gap, 0.0) * inverse_mass +
      settings.collider_contact_ratio / h * std::max(std::min(settings.thickness, start_gap) - end_gap, 0.0);
  const double friction_bound = speed_change + penalty_change;  // both >= 0
  if (!(friction_bound > 0.0)) return 0.0;
  const double normal_impulse = speed_change / inverse_mass;

  // Coulomb friction on the relative tangential velocity: it stops when the change needed is
  // within mu_s times the normal velocity change, else it is reduced by mu_k times that change.
  const Vec3 tangential = velocity - normal_speed * stencil.normal;
  const double tangential_speed = tangential.norm();
  Vec3 tangential_change = Vec3::Zero();
  if (tangential_speed > 0.0) {
    if (tangential_speed <= settings.static_friction * friction_bound) {
      tangential_change = -tangential;
    } else {
      tangential_change = -std::min(settings.kinetic_friction * friction_bound, tangential_speed) /
                          tangential_speed * tangential;
    }
  }
  apply_impulse(step, stencil, normal_impulse * stencil.normal + tangential_change / inverse_mass);
  return friction_bound / inverse_mass;
}

}  // namespace

int apply_proximity_response(CollisionStep& step, PairRange<VertexFacePair> vertex_faces,
                             PairRange<EdgeEdgePair> edge_edges, const ResponseSettings& settings,
                             std::vector<ContactRecord>* records) {
  int acted = 0;
  const Positions& x = step.x_start;

  // Vertex-face pairs: the normal points from the closest point of the triangle to the vertex.
  for (const VertexFacePair& pair : vertex_faces) {
    if (shares_vertex(step, pair)) continue;
    const auto corners = step.triangles.col(pair.triangle);
    const Vec3 p = x.col(pair.vertex);
    const Vec3 a = x.col(corners[0]);
    const Vec3 b = x.col(corners[1]);
    const Vec3 c = x.col(corners[2]);
    const PointTriangleClosest closest = point_triangle_closest(p, a, b, c);
    if (!(closest.distance < settings.thickness)) continue;
    ContactStencil stencil =
        vertex_face_stencil(step, pair.vertex, pair.triangle, closest.barycentric, Vec3::Zero());
    stencil.normal = normal_from(p - closest.closest, (b - a).cross(c - a), relative_velocity(step, stencil));
    const double impulse = respond(step, stencil, closest.distance, settings);
    if (impulse == 0.0) continue;
    ++acted;
    if (records) {
      records->push_back({p, ContactKind::vertex_face, settings.thickness - closest.distance, impulse,
                          pair.vertex, pair.triangle, ContactPartners::cloth_cloth, stencil.normal});
    }
  }

  // Edge-edge pairs: the normal points from the closest point of edge b to that of edge a.
  for (const EdgeEdgePair& pair : edge_edges) {
    if (shares_vertex(step, pair)) continue;
    const Vec3 a0 = x.col(step.edges(0, pair.edge_a));
    const Vec3 a1 = x.col(step.edges(1, pair.edge_a));
    const Vec3 b0 = x.col(step.edges(0, pair.edge_b));
    const Vec3 b1 = x.col(step.edges(1, pair.edge_b));
    const EdgeEdgeClosest closest = edge_edge_closest(a0, a1, b0, b1);
    if (!(closest.distance < settings.thickness)) continue;
    ContactStencil stencil =
        edge_edge_stencil(step, pair.edge_a, pair.edge_b, closest.s, closest.t, Vec3::Zero());
    stencil.normal = normal_from(closest.point_a - closest.point_b, (a1 - a0).cross(b1 - b0),
                                 relative_velocity(step, stencil));
    const double impulse = respond(step, stencil, closest.distance, settings);
    if (impulse == 0.0) continue;
    ++acted;
    if (records) {
      records->push_back({closest.point_a, ContactKind::edge_edge, settings.thickness - closest.distance,
                          impulse, pair.edge_a, pair.edge_b, ContactPartners::cloth_cloth, stencil.normal});
    }
  }
  return acted;
}

}  // namespace weft
