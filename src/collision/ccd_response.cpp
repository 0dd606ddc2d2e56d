#include "collision/ccd_response.hpp"

#include <algorithm>
#include <initializer_list>

#include "collision/edge_edge_ccd.hpp"
#include "collision/vertex_face_ccd.hpp"
#include "core/parallel_chunks.hpp"

namespace weft {

bool swept_boxes_overlap(const Positions& x0, const Positions& x1, std::initializer_list<int> first,
                         std::initializer_list<int> second, double gap) {
  const auto box_of = [&](std::initializer_list<int> vertices, Vec3& lower, Vec3& upper) {
    lower = upper = x0.col(*vertices.begin());
    for (int v : vertices) {
      lower = lower.cwiseMin(x0.col(v)).cwiseMin(x1.col(v));
      upper = upper.cwiseMax(x0.col(v)).cwiseMax(x1.col(v));
    }
  };
  Vec3 lower_a, upper_a, lower_b, upper_b;
  box_of(first, lower_a, upper_a);
  box_of(second, lower_b, upper_b);
  return (lower_a.array() <= upper_b.array() + gap).all() && (lower_b.array() <= upper_a.array() + gap).all();
}

ContactRecord ccd_contact_record(const CollisionStep& step, const CcdCollision& collision, double impulse,
                                 const ResponseSettings& settings) {
  Vec3 position = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    if (collision.stencil.weights[k] > 0.0) {
      const int v = collision.stencil.vertices[k];
      position += collision.stencil.weights[k] *
                  ((1.0 - collision.time) * step.x_start.col(v) + collision.time * step.x_end.col(v));
    }
  }
  return {position,
          collision.kind,
          settings.thickness - collision.distance,
          impulse,
          collision.primitive_a,
          collision.primitive_b,
          ContactPartners::cloth_cloth,
          collision.stencil.normal};
}

std::optional<CcdCollision> detect_collision(const CollisionStep& step, const VertexFacePair& pair,
                                             const ResponseSettings& settings) {
  if (shares_vertex(step, pair)) return std::nullopt;
  const auto corners = step.triangles.col(pair.triangle);
  const Positions& x0 = step.x_start;
  const Positions& x1 = step.x_end;
  if (!swept_boxes_overlap(x0, x1, {pair.vertex}, {corners[0], corners[1], corners[2]},
                           settings.ccd_tolerance)) {
    return std::nullopt;
  }
  const std::optional<VertexFaceImpact> impact = vertex_face_ccd(
      x0.col(pair.vertex), x0.col(corners[0]), x0.col(corners[1]), x0.col(corners[2]), x1.col(pair.vertex),
      x1.col(corners[0]), x1.col(corners[1]), x1.col(corners[2]), settings.ccd_tolerance);
  if (!impact) return std::nullopt;
  return CcdCollision{
      ContactKind::vertex_face,
      pair.vertex,
      pair.triangle,
      impact->time,
      impact->distance,
      vertex_face_stencil(step, pair.vertex, pair.triangle, impact->barycentric, impact->normal)};
}

std::optional<CcdCollision> detect_collision(const CollisionStep& step, const EdgeEdgePair& pair,
                                             const ResponseSettings& settings) {
  if (shares_vertex(step, pair)) return std::nullopt;
  const auto a = step.edges.col(pair.edge_a);
  const auto b = step.edges.col(pair.edge_b);
  const Positions& x0 = step.x_start;
  const Positions& x1 = step.x_end;
  if (!swept_boxes_overlap(x0, x1, {a[0], a[1]}, {b[0], b[1]}, settings.ccd_tolerance)) return std::nullopt;
  const std::optional<EdgeEdgeImpact> impact =
      edge_edge_ccd(x0.col(a[0]), x0.col(a[1]), x0.col(b[0]), x0.col(b[1]), x1.col(a[0]), x1.col(a[1]),
                    x1.col(b[0]), x1.col(b[1]), settings.ccd_tolerance);
  if (!impact) return std::nullopt;
  return CcdCollision{
      ContactKind::edge_edge,
      pair.edge_a,
      pair.edge_b,
      impact->time,
      impact->distance,
      edge_edge_stencil(step, pair.edge_a, pair.edge_b, impact->s, impact->t, impact->normal)};
}

void detect_collisions(const CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                       const std::vector<EdgeEdgePair>& edge_edges, const ResponseSettings& settings,
                       CcdCollisions& collisions) {
  collisions.found.clear();
  const int num_vertex_faces = static_cast<int>(vertex_faces.size());
  const int total = num_vertex_faces + static_cast<int>(edge_edges.size());
  // Contiguous chunks of the pairs, taken by the threads as they come free (the pairs are
  // sorted, so the costly ones near contact bunch together), each keeping its hits in order; the
  // chunks are joined in order, so the list is the same for any number of threads.
  const int chunks = std::clamp(total / 256, 1, detection_chunks);
  if (static_cast<int>(collisions.chunk_found.size()) < chunks) collisions.chunk_found.resize(chunks);
#pragma omp parallel for schedule(dynamic, 1) if (chunks > 1)
  for (int c = 0; c < chunks; ++c) {
    std::vector<CcdCollision>& found = collisions.chunk_found[c];
    found.clear();
    const int end = chunk_begin(c + 1, total, chunks);
    for (int k = chunk_begin(c, total, chunks); k < end; ++k) {
      const std::optional<CcdCollision> collision =
          k < num_vertex_faces ? detect_collision(step, vertex_faces[k], settings)
                               : detect_collision(step, edge_edges[k - num_vertex_faces], settings);
      if (collision) found.push_back(*collision);
    }
  }
  for (int c = 0; c < chunks; ++c) {
    collisions.found.insert(collisions.found.end(), collisions.chunk_found[c].begin(),
                            collisions.chunk_found[c].end());
  }
}

double apply_ccd_impulse(CollisionStep& step, const CcdCollision& collision,
                         const ResponseSettings& settings) {
  const ContactStencil& stencil = collision.stencil;
  const double inverse_mass = inverse_effective_mass(step, stencil);
  if (!(inverse_mass > 0.0)) return 0.0;

  // Target relative normal speed: no approach, and enough separation to restore a gap of
  // ccd_separation * thickness by the end of the step when the pair started closer than that.
  const double h = step.time_step;
  const double start_gap = std::max(relative_start_position(step, stencil).dot(stencil.normal), 0.0);
  const double gap = settings.ccd_separation * settings.thickness;
  const double target_speed = std::max(0.0, (gap - start_gap) / h);
  const double normal_speed = relative_velocity(step, stencil).dot(stencil.normal);
  if (normal_speed >= target_speed) return 0.0;

  // Inelastic impulse along the normal (BFA 2002 section 7.3, mass-weighted as in 7.1).
  const double impulse = (target_speed - normal_speed) / inverse_mass;
  apply_impulse(step, stencil, impulse * stencil.normal);
  return impulse;
}

CcdResponseResult apply_ccd_response(CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                                     const std::vector<EdgeEdgePair>& edge_edges,
                                     const ResponseSettings& settings, std::vector<ContactRecord>* records) {
  CcdResponseResult result;
  // Gauss-Seidel over the pairs: each impulse changes x_end before the next pair is tested.
  const auto handle = [&](const std::optional<CcdCollision>& collision, int& found) {
    if (!collision) return;
    ++found;
    ContactRecord record = ccd_contact_record(step, *collision, 0.0, settings);  // before the motion changes
    record.impulse = apply_ccd_impulse(step, *collision, settings);
    if (record.impulse > 0.0) {
      ++result.impulses;
      if (records) records->push_back(record);
    }
  };
  for (result.passes = 0; result.passes < settings.max_ccd_passes;) {
    int found = 0;
    ++result.passes;
    for (const VertexFacePair& pair : vertex_faces) handle(detect_collision(step, pair, settings), found);
    for (const EdgeEdgePair& pair : edge_edges) handle(detect_collision(step, pair, settings), found);
    if (found == 0) {
      result.clean = true;
      break;
    }
  }
  return result;
}

}  // namespace weft
