#include "collision/ccd_response.hpp"

#include <omp.h>

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
  const int max_threads = std::max(1, omp_get_max_threads());
  if (static_cast<int>(collisions.thread_found.size()) < max_threads) collisions.thread_found.resize(max_threads);
  // Each thread tests a contiguous slice of the pairs and keeps its hits in order; the slices
  // are joined in thread order, so the list is the same for any number of threads.
  int threads = 1;
#pragma omp parallel if (total > 256)
  {
    const int count = omp_get_num_threads();
    const int thread = omp_get_thread_num();
    if (thread == 0) threads = count;
    std::vector<CcdCollision>& found = collisions.thread_found[thread];
    found.clear();
    const int end = chunk_begin(thread + 1, total, count);
    for (int k = chunk_begin(thread, total, count); k < end; ++k) {
      const std::optional<CcdCollision> collision =
          k < num_vertex_faces ? detect_collision(step, vertex_faces[k], settings)
                               : detect_collision(step, edge_edges[k - num_vertex_faces], settings);
      if (collision) found.push_back(*collision);
    }
  }
  for (int t = 0; t < threads; ++t) {
    collisions.found.insert(collisions.found.end(), collisions.thread_found[t].begin(),
                            collisions.thread_found[t].end());
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
