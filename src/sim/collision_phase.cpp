#include "sim/collision_phase.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstring>

#include "collision/contact_impulse.hpp"
#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"
#include "collision/proximity_response.hpp"
#include "core/phase_timer.hpp"

namespace weft {

CollisionPhaseStats& CollisionPhaseStats::operator+=(const CollisionPhaseStats& other) {
  broad_ms += other.broad_ms;
  narrow_ms += other.narrow_ms;
  response_ms += other.response_ms;
  vertex_face_candidates += other.vertex_face_candidates;
  edge_edge_candidates += other.edge_edge_candidates;
  proximity_contacts += other.proximity_contacts;
  ccd_impulses += other.ccd_impulses;
  impact_zone_vertices += other.impact_zone_vertices;
  held_pins += other.held_pins;
  immovable_collisions += other.immovable_collisions;
  edges_over_strain_limit += other.edges_over_strain_limit;
  strain_limited_edges += other.strain_limited_edges;
  largest_correction = std::max(largest_correction, other.largest_correction);
  corrected_vertices += other.corrected_vertices;
  bvh_rebuilds += other.bvh_rebuilds;
  rounds += other.rounds;
  clean = clean && other.clean;
  return *this;
}

void CollisionPhase::set_meshes(const std::vector<Cloth>& cloths, const std::vector<ContactMaterial>& materials,
                                const std::vector<ColliderSurface>& colliders) {
  num_cloths_ = static_cast<int>(cloths.size());
  materials_ = materials;
  colliders_ = colliders;
  meshes_.clear();
  meshes_.resize(cloths.size() + colliders.size());
  max_thickness_ = 0.0;

  // Layout: each mesh's offsets are the running totals of the meshes before it.
  MeshIndexOffsets offsets;
  for (size_t m = 0; m < meshes_.size(); ++m) {
    MeshSlot& slot = meshes_[m];
    const bool is_cloth = m < cloths.size();
    if (is_cloth) {
      const ClothModel& model = cloths[m].model;
      slot.local_triangles = model.triangles;
      slot.num_vertices = static_cast<int>(model.rest_positions.cols());
      slot.thickness = model.thickness;
      slot.soft_body = model.pressure.enabled;
      max_thickness_ = std::max(max_thickness_, model.thickness);
    } else {
      const ColliderSurface& collider = colliders[m - cloths.size()];
      slot.local_triangles = collider.triangles;
      slot.num_vertices = static_cast<int>(collider.rest_positions.cols());
      slot.moves = !collider.motion.is_static();
    }
    slot.topology = build_topology(slot.local_triangles, slot.num_vertices);
    slot.owned = owned_primitives(slot.topology, static_cast<int>(slot.local_triangles.cols()));
    slot.offsets = offsets;
    slot.global_triangles = slot.local_triangles.array() + offsets.vertex;
    slot.vertex_entries = point_entries(offsets.vertex, slot.num_vertices);
    slot.edge_entries = segment_entries(slot.topology.edges, offsets.vertex);
    offsets = next_offsets(offsets, slot.num_vertices, static_cast<int>(slot.local_triangles.cols()),
                           slot.topology.num_edges());
  }

  // Combined arrays.
  x_start_.resize(3, offsets.vertex);
  x_end_.resize(3, offsets.vertex);
  velocity_.resize(3, offsets.vertex);
  inverse_mass_.setZero(offsets.vertex);
  triangles_.resize(3, offsets.triangle);
  edges_.resize(2, offsets.edge);
  vertex_mesh_.assign(offsets.vertex, 0);
  holdable_.assign(offsets.vertex, 0);
  edge_rest_length_.assign(offsets.edge, 0.0);
  for (size_t m = 0; m < meshes_.size(); ++m) {
    const MeshSlot& slot = meshes_[m];
    triangles_.middleCols(slot.offsets.triangle, slot.global_triangles.cols()) = slot.global_triangles;
    edges_.middleCols(slot.offsets.edge, slot.topology.num_edges()) =
        slot.topology.edges.array() + slot.offsets.vertex;
    std::fill_n(vertex_mesh_.begin() + slot.offsets.vertex, slot.num_vertices, static_cast<int>(m));
    if (m < cloths.size()) {
      std::fill_n(holdable_.begin() + slot.offsets.vertex, slot.num_vertices, 1);
      inverse_mass_.segment(slot.offsets.vertex, slot.num_vertices) = cloths[m].model.inverse_mass;
      const Positions& rest = cloths[m].model.rest_positions;
      for (int e = 0; e < slot.topology.num_edges(); ++e) {
        edge_rest_length_[slot.offsets.edge + e] =
            (rest.col(slot.topology.edges(1, e)) - rest.col(slot.topology.edges(0, e))).norm();
      }
    } else {
      // Static colliders sit still for good; kinematic ones are posed every step.
      const ColliderSurface& collider = colliders[m - cloths.size()];
      collider.motion.place(collider.rest_positions, 0.0, x_start_.middleCols(slot.offsets.vertex, slot.num_vertices));
      x_end_.middleCols(slot.offsets.vertex, slot.num_vertices) =
          x_start_.middleCols(slot.offsets.vertex, slot.num_vertices);
      velocity_.middleCols(slot.offsets.vertex, slot.num_vertices).setZero();
    }
  }
  const int num_groups = num_cloths_ * static_cast<int>(meshes_.size());
  near_vertex_faces_.begin_counting(num_groups);
  near_edge_edges_.begin_counting(num_groups);
}

void CollisionPhase::update_parameters(const std::vector<Cloth>& cloths,
                                       const std::vector<ContactMaterial>& materials,
                                       const std::vector<Collider>& colliders) {
  std::copy(materials.begin(), materials.end(), materials_.begin());
  max_thickness_ = 0.0;
  for (int c = 0; c < num_cloths_; ++c) {
    meshes_[c].thickness = cloths[c].model.thickness;
    max_thickness_ = std::max(max_thickness_, meshes_[c].thickness);
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    colliders_[k].static_friction = colliders[k].static_friction;
    colliders_[k].kinetic_friction = colliders[k].friction;
  }
}

void CollisionPhase::begin_step(const std::vector<Cloth>& cloths, double t) {
  step_start_time_ = t;
  for (int c = 0; c < num_cloths_; ++c) {
    x_start_.middleCols(meshes_[c].offsets.vertex, meshes_[c].num_vertices) = cloths[c].state.x;
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    const MeshSlot& slot = meshes_[num_cloths_ + k];
    if (!slot.moves) continue;
    colliders_[k].motion.place(colliders_[k].rest_positions, t,
                               x_start_.middleCols(slot.offsets.vertex, slot.num_vertices));
  }
}

// Phase: the integrator's candidate motion and the colliders' scripted one, in combined arrays.
void CollisionPhase::gather_motion(const std::vector<Cloth>& cloths, double t, double h) {
  time_step_ = h;
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshSlot& slot = meshes_[c];
    x_end_.middleCols(slot.offsets.vertex, slot.num_vertices) = cloths[c].state.x;
    velocity_.middleCols(slot.offsets.vertex, slot.num_vertices) = cloths[c].state.v;
  }
  for (size_t k = 0; k < colliders_.size(); ++k) {
    const MeshSlot& slot = meshes_[num_cloths_ + k];
    if (!slot.moves) continue;
    auto end = x_end_.middleCols(slot.offsets.vertex, slot.num_vertices);
    colliders_[k].motion.place(colliders_[k].rest_positions, t + h, end);
    velocity_.middleCols(slot.offsets.vertex, slot.num_vertices) =
        (end - x_start_.middleCols(slot.offsets.vertex, slot.num_vertices)) / h;
  }
  motion_valid_ = x_end_.allFinite() && velocity_.allFinite() &&
                  (x_end_ - x_start_).cwiseAbs().maxCoeff() <= settings.max_step_displacement;
}

CollisionStep CollisionPhase::make_step() {
  return CollisionStep{x_start_, x_end_, velocity_, inverse_mass_, triangles_, edges_, time_step_, &holdable_};
}

// Swept boxes over the current motion (each mesh's triangles, vertices and edges), each inflated
// by half the largest thickness so that two boxes overlap whenever their primitives come within a
// thickness; a hierarchy that refitting has made too loose is built again.
void CollisionPhase::refit_bounding_volumes() {
  for (MeshSlot& slot : meshes_) {
    if (slot.built && !slot.moves) continue;
    update_bounding_volumes(slot, x_start_, x_end_);
  }
}

void CollisionPhase::update_bounding_volumes(MeshSlot& slot, const Positions& from, const Positions& to) {
  const auto update = [&](Bvh& bvh, const Triangles& entries) {
    if (!slot.built || bvh.needs_rebuild()) {
      bvh.build(from, to, entries, box_margin(), settings.bvh);
      ++stats_.bvh_rebuilds;
    } else {
      bvh.refit(from, to, box_margin());
    }
  };
  update(slot.bvh, slot.global_triangles);
  update(slot.vertex_bvh, slot.vertex_entries);
  update(slot.edge_bvh, slot.edge_entries);
  slot.built = true;
}

PrimitiveMesh CollisionPhase::primitive_mesh(const MeshSlot& slot) const {
  return PrimitiveMesh{slot.local_triangles, slot.topology, slot.offsets, slot.bvh,
                       slot.vertex_bvh,      slot.edge_bvh};
}

// Primitive pairs whose swept boxes come within the largest thickness (self, cloth-cloth,
// cloth-collider; colliders never meet each other), queried primitive against primitive
// (collision/primitive_queries.hpp); pairs of infinite-mass vertices only are dropped. Self pairs
// of primitives on neighbouring triangles are included: a hem folding through the row next to
// it meets only triangles that share a vertex with its own (docs/collision.md).
void CollisionPhase::query_candidates(CollisionCandidates& candidates) {
  candidates.clear();
  vertex_lower_.noalias() = x_start_.cwiseMin(x_end_);
  vertex_upper_.noalias() = x_start_.cwiseMax(x_end_);
  const SweptVertexBoxes boxes{vertex_lower_, vertex_upper_, max_thickness_};
  for (int c = 0; c < num_cloths_; ++c) {
    MeshSlot& cloth = meshes_[c];
    if (materials_[c].self_collision) {
      cloth.culling.update(cloth.bvh, x_start_, x_end_, max_thickness_, settings.self_culling);
      if (settings.self_culling.enabled) {
        append_self_candidates_culled(primitive_mesh(cloth), cloth.owned, boxes, cloth.culling.culled(),
                                      nullptr, buffers_, candidates);
      } else {
        append_self_primitive_candidates(primitive_mesh(cloth), boxes, buffers_, candidates);
      }
    }
    for (size_t other = c + 1; other < meshes_.size(); ++other) {
      append_primitive_candidates_between(primitive_mesh(cloth), primitive_mesh(meshes_[other]), boxes,
                                          buffers_, candidates);
    }
  }
  sort_candidates(candidates);
  drop_immovable_pairs(candidates, &immovable_candidates_);
}

void CollisionPhase::drop_immovable_pairs(CollisionCandidates& candidates,
                                          CollisionCandidates* immovable) const {
  const auto infinite = [&](int v) { return inverse_mass_[v] == 0.0; };
  const auto vertex_face_immovable = [&](const VertexFacePair& pair) {
    const auto corners = triangles_.col(pair.triangle);
    return infinite(pair.vertex) && infinite(corners[0]) && infinite(corners[1]) && infinite(corners[2]);
  };
  const auto edge_edge_immovable = [&](const EdgeEdgePair& pair) {
    return infinite(edges_(0, pair.edge_a)) && infinite(edges_(1, pair.edge_a)) &&
           infinite(edges_(0, pair.edge_b)) && infinite(edges_(1, pair.edge_b));
  };
  // Both parts keep the candidates' sorted order (and no scratch is allocated once grown).
  const auto split = [](auto& pairs, auto* kept_aside, const auto& is_immovable) {
    if (kept_aside) {
      kept_aside->clear();
      for (const auto& pair : pairs) {
        if (is_immovable(pair)) kept_aside->push_back(pair);
      }
    }
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(), is_immovable), pairs.end());
  };
  split(candidates.vertex_face, immovable ? &immovable->vertex_face : nullptr, vertex_face_immovable);
  split(candidates.edge_edge, immovable ? &immovable->edge_edge : nullptr, edge_edge_immovable);
}

// Phase: broad phase.
void CollisionPhase::find_candidates() {
  const auto start = PhaseClock::now();
  refit_bounding_volumes();
  query_candidates(candidates_);
  stats_.vertex_face_candidates += static_cast<int>(candidates_.vertex_face.size());
  stats_.edge_edge_candidates += static_cast<int>(candidates_.edge_edge.size());
  stats_.broad_ms += milliseconds_since(start);
}

// Material pairs: group a * n_meshes + b for the cloth a and the mesh b >= a it meets.
int CollisionPhase::material_group(int mesh_a, int mesh_b) const {
  if (mesh_a > mesh_b) std::swap(mesh_a, mesh_b);
  return mesh_a * static_cast<int>(meshes_.size()) + mesh_b;
}

ResponseSettings CollisionPhase::response_settings(int group) const {
  const int a = group / static_cast<int>(meshes_.size());
  const int b = group % static_cast<int>(meshes_.size());
  ResponseSettings response = ccd_settings();
  response.thickness = std::max(meshes_[a].thickness, meshes_[b].thickness);
  if (b >= num_cloths_) {
    const ColliderSurface& collider = colliders_[b - num_cloths_];
    response.static_friction = collider.static_friction;
    response.kinetic_friction = collider.kinetic_friction;
    response.collider_contact_ratio = settings.collider_contact_ratio;
  } else {
    response.static_friction = 0.5 * (materials_[a].static_friction + materials_[b].static_friction);
    response.kinetic_friction = 0.5 * (materials_[a].kinetic_friction + materials_[b].kinetic_friction);
  }
  return response;
}

ResponseSettings CollisionPhase::ccd_settings() const {
  ResponseSettings response;
  response.thickness = max_thickness_;
  response.repulsion_stiffness = settings.repulsion_stiffness;
  response.ccd_tolerance = settings.ccd_tolerance;
  response.ccd_separation = settings.ccd_separation;
  response.max_ccd_passes = settings.max_ccd_passes;
  response.max_impact_zone_passes = settings.max_impact_zone_passes;
  response.penalty_stiffness = settings.penalty_stiffness;
  return response;
}

double CollisionPhase::pair_thickness(int vertex_a, int vertex_b) const {
  return std::max(meshes_[vertex_mesh_[vertex_a]].thickness, meshes_[vertex_mesh_[vertex_b]].thickness);
}

int CollisionPhase::vertex_face_group(const VertexFacePair& pair) const {
  return material_group(vertex_mesh_[pair.vertex], vertex_mesh_[triangles_(0, pair.triangle)]);
}

int CollisionPhase::edge_edge_group(const EdgeEdgePair& pair) const {
  return material_group(vertex_mesh_[edges_(0, pair.edge_a)], vertex_mesh_[edges_(0, pair.edge_b)]);
}

// Phase: pairs closer than their thickness at the start of the step (tested in parallel), then
// repulsion and friction impulses group by group of material pairs.
void CollisionPhase::apply_proximity() {
  auto start = PhaseClock::now();
  const auto& vertex_faces = candidates_.vertex_face;
  const auto& edge_edges = candidates_.edge_edge;
  near_vertex_face_.assign(vertex_faces.size(), 0);
  near_edge_edge_.assign(edge_edges.size(), 0);
  const Positions& x = x_start_;
  const int num_vertex_faces = static_cast<int>(vertex_faces.size());
  const int num_edge_edges = static_cast<int>(edge_edges.size());
#pragma omp parallel for schedule(static) if (num_vertex_faces > 1024)
  for (int k = 0; k < num_vertex_faces; ++k) {
    const VertexFacePair& pair = vertex_faces[k];
    const auto corners = triangles_.col(pair.triangle);
    const double thickness = pair_thickness(pair.vertex, corners[0]);
    // Boxes farther apart than the thickness spare the closest-point computation (most candidates).
    if (!swept_boxes_overlap(x, x, {pair.vertex}, {corners[0], corners[1], corners[2]}, thickness)) {
      near_vertex_face_[k] = 0;
      continue;
    }
    const double distance =
        point_triangle_closest(x.col(pair.vertex), x.col(corners[0]), x.col(corners[1]), x.col(corners[2]))
            .distance;
    near_vertex_face_[k] = distance < thickness;
  }
#pragma omp parallel for schedule(static) if (num_edge_edges > 1024)
  for (int k = 0; k < num_edge_edges; ++k) {
    const EdgeEdgePair& pair = edge_edges[k];
    const auto a = edges_.col(pair.edge_a);
    const auto b = edges_.col(pair.edge_b);
    const double thickness = pair_thickness(a[0], b[0]);
    if (!swept_boxes_overlap(x, x, {a[0], a[1]}, {b[0], b[1]}, thickness)) {
      near_edge_edge_[k] = 0;
      continue;
    }
    const double distance = edge_edge_closest(x.col(a[0]), x.col(a[1]), x.col(b[0]), x.col(b[1])).distance;
    near_edge_edge_[k] = distance < thickness;
  }
  // The near pairs by material group, in one array per kind, no larger than the candidates.
  const int num_groups = near_vertex_faces_.num_groups();
  near_vertex_faces_.pairs.reserve(vertex_faces.capacity());
  near_edge_edges_.pairs.reserve(edge_edges.capacity());
  near_vertex_faces_.begin_counting(num_groups);
  near_edge_edges_.begin_counting(num_groups);
  for (int k = 0; k < num_vertex_faces; ++k) {
    if (near_vertex_face_[k]) near_vertex_faces_.count(vertex_face_group(vertex_faces[k]));
  }
  for (int k = 0; k < num_edge_edges; ++k) {
    if (near_edge_edge_[k]) near_edge_edges_.count(edge_edge_group(edge_edges[k]));
  }
  near_vertex_faces_.place_counted();
  near_edge_edges_.place_counted();
  for (int k = 0; k < num_vertex_faces; ++k) {
    if (near_vertex_face_[k]) near_vertex_faces_.place(vertex_face_group(vertex_faces[k]), vertex_faces[k]);
  }
  for (int k = 0; k < num_edge_edges; ++k) {
    if (near_edge_edge_[k]) near_edge_edges_.place(edge_edge_group(edge_edges[k]), edge_edges[k]);
  }
  stats_.narrow_ms += milliseconds_since(start);

  start = PhaseClock::now();
  CollisionStep step = make_step();
  const size_t first_record = records_.size();
  for (int group = 0; group < num_groups; ++group) {
    const PairRange<VertexFacePair> group_vertex_faces = near_vertex_faces_.group(group);
    const PairRange<EdgeEdgePair> group_edge_edges = near_edge_edges_.group(group);
    if (group_vertex_faces.empty() && group_edge_edges.empty()) continue;
    stats_.proximity_contacts += apply_proximity_response(step, group_vertex_faces, group_edge_edges,
                                                          response_settings(group), &records_);
  }
  label_records(first_record);
  stats_.response_ms += milliseconds_since(start);
}

// Phase: edges the impulses (or the solve) left stretched past the limit are shortened. The
// motion it changed has not been tested for collisions, so the step is not clean until it is.
void CollisionPhase::limit_strain() {
  if (!(settings.strain_limit > 0.0)) return;
  const auto start = PhaseClock::now();
  CollisionStep step = make_step();
  const StrainLimitResult result =
      limit_edge_strain(step, edge_rest_length_, settings.strain_limit, settings.strain_limit_sweeps);
  stats_.strain_limited_edges += result.corrected_edges;
  if (result.sweeps > 0) stats_.clean = false;
  stats_.response_ms += milliseconds_since(start);
}

void CollisionPhase::penalty_contacts(int cloth, double stiffness, ContactPenalty& penalty) {
  const int first = meshes_[cloth].offsets.vertex;
  const Positions& x = x_start_;
  const CollisionStep step = make_step();
  // The stencil's vertices in the cloth become its own; the others fold into the offset.
  const auto add = [&](const ContactStencil& stencil, const Vec3& gap, double thickness) {
    const double distance = gap.norm();
    if (!(distance > 1e-9 * thickness) || !(distance < 2.0 * thickness)) return;
    PenaltyContact contact{{-1, -1, -1, -1}, stencil.weights, gap / distance, 0.0, thickness, stiffness};
    bool touches = false;
    for (int k = 0; k < 4; ++k) {
      const int v = stencil.vertices[k];
      if (vertex_mesh_[v] == cloth) {
        contact.vertices[k] = v - first;
        touches = true;
      } else {
        contact.offset += stencil.weights[k] * contact.normal.dot(x.col(v));
      }
    }
    if (touches) penalty.contacts.push_back(contact);
  };
  for (int group = 0; group < near_vertex_faces_.num_groups(); ++group) {
    for (const VertexFacePair& pair : near_vertex_faces_.group(group)) {
      const auto corners = triangles_.col(pair.triangle);
      const PointTriangleClosest closest =
          point_triangle_closest(x.col(pair.vertex), x.col(corners[0]), x.col(corners[1]), x.col(corners[2]));
      add(vertex_face_stencil(step, pair.vertex, pair.triangle, closest.barycentric, Vec3::Zero()),
          x.col(pair.vertex) - closest.closest, pair_thickness(pair.vertex, corners[0]));
    }
    for (const EdgeEdgePair& pair : near_edge_edges_.group(group)) {
      const auto a = edges_.col(pair.edge_a);
      const auto b = edges_.col(pair.edge_b);
      const EdgeEdgeClosest closest = edge_edge_closest(x.col(a[0]), x.col(a[1]), x.col(b[0]), x.col(b[1]));
      add(edge_edge_stencil(step, pair.edge_a, pair.edge_b, closest.s, closest.t, Vec3::Zero()),
          closest.point_a - closest.point_b, pair_thickness(a[0], b[0]));
    }
  }
}

void CollisionPhase::collider_contacts(int cloth, const Cloth& state, double h, const Vec3& gravity,
                                       double ratio, ContactPenalty& penalty) {
  const MeshSlot& slot = meshes_[cloth];
  const double thickness = slot.thickness;
  const double fall = h * h * gravity.norm();
  // The colliders at the step's end, where the solve's positions are compared with them (only
  // their columns are written; the same size every step: no allocation once grown).
  if (reach_positions_.cols() != x_start_.cols()) reach_positions_.setZero(3, x_start_.cols());
  for (size_t k = 0; k < colliders_.size(); ++k) {
    const MeshSlot& collider = meshes_[num_cloths_ + k];
    auto end = reach_positions_.middleCols(collider.offsets.vertex, collider.num_vertices);
    if (collider.moves) {
      colliders_[k].motion.place(colliders_[k].rest_positions, step_start_time_ + h, end);
    } else {
      end = x_start_.middleCols(collider.offsets.vertex, collider.num_vertices);
    }
  }
  const Positions& at_end = reach_positions_;
  // A collider the broad phase has not built yet (the first step, or the first after a restore):
  // swept over this step, so that a resumed run finds the contacts the original did.
  for (size_t k = 0; k < colliders_.size(); ++k) {
    MeshSlot& collider = meshes_[num_cloths_ + k];
    if (!collider.built) update_bounding_volumes(collider, x_start_, at_end);
  }
  // One slot a vertex and collider, filled in parallel (each thread with its own triangle list),
  // then appended in vertex order: the same contacts in the same order on any thread count.
  const int num_colliders = static_cast<int>(colliders_.size());
  const size_t num_slots = static_cast<size_t>(slot.num_vertices) * num_colliders;
  if (reach_slots_.size() < num_slots) reach_slots_.resize(num_slots);
  if (reach_found_.size() < num_slots) reach_found_.resize(num_slots);
  const int threads = std::max(1, omp_get_max_threads());
  if (static_cast<int>(reach_triangles_.size()) < threads) reach_triangles_.resize(threads);
#pragma omp parallel for schedule(static) if (slot.num_vertices > 1024)
  for (int v = 0; v < slot.num_vertices; ++v) {
    std::vector<int>& triangles = reach_triangles_[omp_get_thread_num()];
    for (int k = 0; k < num_colliders; ++k) reach_found_[static_cast<size_t>(v) * num_colliders + k] = 0;
    const double inverse_mass = state.model.inverse_mass[v];
    if (!(inverse_mass > 0.0)) continue;
    const Vec3 x = state.state.x.col(v);
    const double reach = 2.0 * (h * state.state.v.col(v).norm() + fall) + thickness;
    Aabb box;
    box.grow(x - Vec3::Constant(reach));
    box.grow(x + Vec3::Constant(reach));
    for (int k = 0; k < num_colliders; ++k) {
      const MeshSlot& collider = meshes_[num_cloths_ + k];
      find_triangles_in_box(collider.bvh, box, triangles);
      double nearest = reach;
      Vec3 closest_point = Vec3::Zero();
      for (const int t : triangles) {
        const auto corners = collider.bvh.triangles().col(t);
        const PointTriangleClosest closest =
            point_triangle_closest(x, at_end.col(corners[0]), at_end.col(corners[1]), at_end.col(corners[2]));
        const double distance = (x - closest.closest).norm();
        if (distance < nearest) {
          nearest = distance;
          closest_point = closest.closest;
        }
      }
      if (!(nearest < reach) || !(nearest > 1e-9 * thickness)) continue;
      const Vec3 normal = (x - closest_point) / nearest;
      const size_t at = static_cast<size_t>(v) * num_colliders + k;
      reach_slots_[at] = PenaltyContact{{v, -1, -1, -1},
                                        {1.0, 0.0, 0.0, 0.0},
                                        normal,
                                        -normal.dot(closest_point),
                                        std::min(thickness, nearest),
                                        ratio / (inverse_mass * h * h)};
      reach_found_[at] = 1;
    }
  }
  for (size_t at = 0; at < num_slots; ++at) {
    if (reach_found_[at]) penalty.contacts.push_back(reach_slots_[at]);
  }
}

std::vector<std::array<int, 3>> CollisionPhase::near_pairs() const {
  std::vector<std::array<int, 3>> pairs;
  for (int group = 0; group < near_vertex_faces_.num_groups(); ++group) {
    for (const VertexFacePair& pair : near_vertex_faces_.group(group)) pairs.push_back({0, pair.vertex, pair.triangle});
    for (const EdgeEdgePair& pair : near_edge_edges_.group(group)) pairs.push_back({1, pair.edge_a, pair.edge_b});
  }
  return pairs;
}

void CollisionPhase::set_near_pairs(const std::vector<std::array<int, 3>>& pairs) {
  const int vertices = static_cast<int>(x_start_.cols());
  const int triangles = static_cast<int>(triangles_.cols());
  const int edges = static_cast<int>(edges_.cols());
  const auto in = [](int index, int size) { return index >= 0 && index < size; };
  const int num_groups = near_vertex_faces_.num_groups();
  near_vertex_faces_.begin_counting(num_groups);
  near_edge_edges_.begin_counting(num_groups);
  // Counted, then placed, in the order given (the order near_pairs() wrote them in).
  for (const bool placing : {false, true}) {
    for (const auto& [kind, a, b] : pairs) {
      if (kind == 0 && in(a, vertices) && in(b, triangles)) {
        const VertexFacePair pair{a, b};
        if (placing) {
          near_vertex_faces_.place(vertex_face_group(pair), pair);
        } else {
          near_vertex_faces_.count(vertex_face_group(pair));
        }
      } else if (kind == 1 && in(a, edges) && in(b, edges)) {
        const EdgeEdgePair pair{a, b};
        if (placing) {
          near_edge_edges_.place(edge_edge_group(pair), pair);
        } else {
          near_edge_edges_.count(edge_edge_group(pair));
        }
      }
    }
    if (!placing) {
      near_vertex_faces_.place_counted();
      near_edge_edges_.place_counted();
    }
  }
}

// Phase: continuous detection of every candidate over the corrected motion (in parallel), then
// an inelastic impulse on each collision found, pass after pass until one finds none. A pass
// after the first tests only the candidates with a vertex of a collision the pass before found:
// the impulses moved no other vertex, and a pair's detection depends on its own vertices' motion
// alone, so every other pair is still free of collisions (the passes find what testing every
// candidate would, in the same order).
void CollisionPhase::apply_ccd_impulses() {
  CollisionStep step = make_step();
  const ResponseSettings response = ccd_settings();
  const size_t first_record = records_.size();
  ++stats_.rounds;
  stats_.clean = false;
  clean_snapshot_ = false;
  const CollisionCandidates* tested = &candidates_;
  for (int pass = 0; pass < settings.max_ccd_passes; ++pass) {
    auto start = PhaseClock::now();
    detect_collisions(step, tested->vertex_face, tested->edge_edge, response, collisions_);
    stats_.narrow_ms += milliseconds_since(start);
    if (collisions_.empty()) {
      stats_.clean = true;
      clean_x_end_ = x_end_;
      clean_snapshot_ = true;
      break;
    }
    start = PhaseClock::now();
    for (const CcdCollision& collision : collisions_.found) {
      ContactRecord record = ccd_contact_record(step, collision, 0.0, response);  // before the motion changes
      record.impulse = apply_ccd_impulse(step, collision, response);
      if (record.impulse > 0.0) {
        ++stats_.ccd_impulses;
        records_.push_back(record);
      }
    }
    stats_.response_ms += milliseconds_since(start);
    if (pass + 1 < settings.max_ccd_passes) {
      start = PhaseClock::now();
      retest_flags_.assign(x_end_.cols(), 0);
      for (const CcdCollision& collision : collisions_.found) {
        for (const int v : collision.stencil.vertices) {
          if (v >= 0) retest_flags_[v] = 1;
        }
      }
      list_pairs_touching(retest_flags_, retested_);
      tested = &retested_;
      stats_.narrow_ms += milliseconds_since(start);
    }
  }
  label_records(first_record);
}

void CollisionPhase::list_pairs_touching(const std::vector<char>& flags, CollisionCandidates& out) const {
  const auto flagged = [&](int v) { return flags[v] != 0; };
  out.vertex_face.clear();
  out.edge_edge.clear();
  for (const VertexFacePair& pair : candidates_.vertex_face) {
    const auto corners = triangles_.col(pair.triangle);
    if (flagged(pair.vertex) || flagged(corners[0]) || flagged(corners[1]) || flagged(corners[2])) {
      out.vertex_face.push_back(pair);
    }
  }
  for (const EdgeEdgePair& pair : candidates_.edge_edge) {
    if (flagged(edges_(0, pair.edge_a)) || flagged(edges_(1, pair.edge_a)) ||
        flagged(edges_(0, pair.edge_b)) || flagged(edges_(1, pair.edge_b))) {
      out.edge_edge.push_back(pair);
    }
  }
}

// Phase: what the impulses left colliding (or, with a strain limit, stretched past it) moves as
// rigid zones. limit_strain marks the step unclean whenever it moved anything, so the zones run
// whenever the limit may not hold.
void CollisionPhase::apply_impact_zones() {
  if (stats_.clean) return;
  const auto start = PhaseClock::now();
  CollisionStep step = make_step();
  // With a strain limit, edges still over it join zones too (impact_zones.hpp).
  const StrainBound strain{edge_rest_length_, settings.strain_limit};
  // When the CCD passes left the motion clean, only the strain limiter has moved vertices since: a
  // pair none of whose vertices moved is still free of collisions (detection reads its vertices'
  // motion alone), so the zones' first detection tests the others only, and finds what testing
  // every candidate would, in the same order.
  const CollisionCandidates* first_pass = nullptr;
  if (clean_snapshot_) {
    retest_flags_.assign(x_end_.cols(), 0);
    for (Eigen::Index v = 0; v < x_end_.cols(); ++v) {
      retest_flags_[v] =
          std::memcmp(x_end_.col(v).data(), clean_x_end_.col(v).data(), 3 * sizeof(double)) != 0;
    }
    list_pairs_touching(retest_flags_, zone_first_pairs_);
    first_pass = &zone_first_pairs_;
  }
  const ImpactZoneResult zones =
      resolve_impact_zones(step, candidates_.vertex_face, candidates_.edge_edge, ccd_settings(),
                           zone_workspace_, settings.strain_limit > 0.0 ? &strain : nullptr, first_pass);
  stats_.impact_zone_vertices += zones.zone_vertices;
  stats_.held_pins += zones.held;
  // Pins held at their start did not follow their script: the step is not reported clean. Edges
  // the zones left over the strain limit are not collisions: count_edges_over_limit reports them.
  stats_.clean = zones.collision_free && zones.held == 0;
  stats_.response_ms += milliseconds_since(start);
}

// Phase: the corrected motion may have left the boxes the candidates were found for, or undone
// what let self-collision culling skip a region; if so, the candidates are brought up to date
// and the new ones tested. Returns true when they collide.
//
// The candidates hold every primitive pair whose vertex boxes (vertex_lower_/upper_, the swept
// boxes of the step's first motion) are within the thickness t of each other (triangle boxes
// inflated by t/2 each, then the primitive filter's gap t). A pair that touches (within the
// continuous tests' eta) over a motion keeping every vertex within s = (t - eta)/2 of its box
// had boxes within eta + 2s = t: it is a candidate. A vertex that went farther ("escaped") has
// its box grown to hold its new motion, and the triangles around it are queried again against
// every mesh with the grown boxes, which finds every pair those boxes bring within t; pairs
// of two unchanged boxes were candidates already. Only the new pairs need testing when the last
// detection over the old ones was clean.
bool CollisionPhase::verify_motion() {
  auto start = PhaseClock::now();
  const double slack = std::max(0.0, 0.5 * (max_thickness_ - settings.ccd_tolerance));
  escaped_vertices_.clear();
  for (int v = 0; v < x_end_.cols(); ++v) {
    const auto p = x_end_.col(v).array();
    if ((p < vertex_lower_.col(v).array() - slack).any() || (p > vertex_upper_.col(v).array() + slack).any()) {
      escaped_vertices_.push_back(v);
    }
  }
  // Self-collision culling was decided on the uncorrected motion; a region it skipped must
  // still pass its tests (normal cone, unfolded contour) on the corrected one, else the pairs
  // within it are walked now (query_broken_regions).
  bool culling_holds = true;
  for (int c = 0; c < num_cloths_; ++c) {
    MeshSlot& slot = meshes_[c];
    slot.broken_regions.clear();
    if (!materials_[c].self_collision || !settings.self_culling.enabled) continue;
    culled_before_ = slot.culling.culled();
    slot.culling.update(slot.bvh, x_start_, x_end_, max_thickness_, settings.self_culling);
    const std::vector<char>& culled_now = slot.culling.culled();
    for (size_t k = 0; k < culled_before_.size(); ++k) {
      if (culled_before_[k] && !culled_now[k]) slot.broken_regions.push_back(static_cast<int>(k));
    }
    culling_holds = culling_holds && slot.broken_regions.empty();
  }
  if (escaped_vertices_.empty() && culling_holds) {
    stats_.broad_ms += milliseconds_since(start);
    return false;
  }
  query_escaped_candidates(verify_candidates_);
  if (!culling_holds) query_broken_regions(verify_candidates_);
  merge_new_candidates(candidates_, verify_candidates_);
  stats_.broad_ms += milliseconds_since(start);

  start = PhaseClock::now();
  const CollisionCandidates& tested = stats_.clean ? verify_candidates_ : candidates_;
  CollisionStep step = make_step();
  detect_collisions(step, tested.vertex_face, tested.edge_edge, ccd_settings(), collisions_);
  stats_.narrow_ms += milliseconds_since(start);
  // Found collisions make the step unclean until a next round resolves them; when the rounds
  // run out first, the step is reported unclean instead of silently keeping them.
  if (!collisions_.empty()) stats_.clean = false;
  return !collisions_.empty();
}

// verify_motion's update for culling that stopped holding: the self pairs within each region
// culled when the candidates were found and not culled on the corrected motion, walked with the
// boxes (query_escaped_candidates grew them first) and the culling of the corrected motion, which
// may cull smaller regions inside. Merged into `candidates` (sorted); pairs nothing can move
// join immovable_candidates_.
void CollisionPhase::query_broken_regions(CollisionCandidates& candidates) {
  const SweptVertexBoxes boxes{vertex_lower_, vertex_upper_, max_thickness_};
  region_candidates_.clear();
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshSlot& slot = meshes_[c];
    if (slot.broken_regions.empty()) continue;
    append_self_candidates_culled(primitive_mesh(slot), slot.owned, boxes, slot.culling.culled(),
                                  &slot.broken_regions, buffers_, region_candidates_);
  }
  sort_candidates(region_candidates_);
  drop_immovable_pairs(region_candidates_, &region_immovable_);
  immovable_candidates_.vertex_face.insert(immovable_candidates_.vertex_face.end(),
                                           region_immovable_.vertex_face.begin(),
                                           region_immovable_.vertex_face.end());
  immovable_candidates_.edge_edge.insert(immovable_candidates_.edge_edge.end(),
                                         region_immovable_.edge_edge.begin(),
                                         region_immovable_.edge_edge.end());
  sort_candidates(immovable_candidates_);
  merge_new_candidates(candidates, region_candidates_);
}

// verify_motion's update: grows the boxes of escaped_vertices_ to hold their motion, refits the
// hierarchies over the boxes and writes the candidates with an escaped vertex against every mesh
// (self pairs within culled regions included), sorted.
void CollisionPhase::query_escaped_candidates(CollisionCandidates& candidates) {
  candidates.clear();
  escaped_flags_.assign(x_end_.cols(), 0);
  for (const int v : escaped_vertices_) {
    vertex_lower_.col(v) = vertex_lower_.col(v).cwiseMin(x_end_.col(v));
    vertex_upper_.col(v) = vertex_upper_.col(v).cwiseMax(x_end_.col(v));
    escaped_flags_[v] = 1;
  }
  // A box over the vertices' boxes is the box over both ends of their motion: the hierarchies'
  // boxes are the last refit's but where an escaped vertex's box grew (Bvh::refit_moved). Only
  // cloths move in the response, and a cloth without escaped vertices keeps its boxes.
  for (int c = 0; c < num_cloths_; ++c) {
    MeshSlot& slot = meshes_[c];
    const auto first = escaped_flags_.begin() + slot.offsets.vertex;
    if (std::find(first, first + slot.num_vertices, 1) != first + slot.num_vertices) {
      slot.bvh.refit_moved(vertex_lower_, vertex_upper_, box_margin(), escaped_flags_);
      slot.vertex_bvh.refit_moved(vertex_lower_, vertex_upper_, box_margin(), escaped_flags_);
      slot.edge_bvh.refit_moved(vertex_lower_, vertex_upper_, box_margin(), escaped_flags_);
    }
  }
  const SweptVertexBoxes boxes{vertex_lower_, vertex_upper_, max_thickness_};
  for (int c = 0; c < num_cloths_; ++c) {
    const PrimitiveMesh cloth = primitive_mesh(meshes_[c]);
    list_moved_primitives(cloth, escaped_flags_, escaped_primitives_);
    if (escaped_primitives_.empty()) continue;
    if (materials_[c].self_collision) {
      append_moved_primitive_candidates(cloth, escaped_primitives_, cloth, true, boxes, box_triangles_,
                                        candidates);
    }
    for (size_t other = 0; other < meshes_.size(); ++other) {
      if (other == static_cast<size_t>(c)) continue;
      append_moved_primitive_candidates(cloth, escaped_primitives_, primitive_mesh(meshes_[other]), false,
                                        boxes, box_triangles_, candidates);
    }
  }
  sort_candidates(candidates);
  drop_immovable_pairs(candidates, nullptr);  // an escaped vertex has finite mass: none to keep
}

void CollisionPhase::check_immovable_pairs() {
  if (immovable_candidates_.vertex_face.empty() && immovable_candidates_.edge_edge.empty()) return;
  const auto start = PhaseClock::now();
  detect_collisions(make_step(), immovable_candidates_.vertex_face, immovable_candidates_.edge_edge,
                    ccd_settings(), collisions_);
  stats_.narrow_ms += milliseconds_since(start);
  if (collisions_.empty()) return;
  stats_.immovable_collisions += static_cast<int>(collisions_.found.size());
  stats_.clean = false;
}

void CollisionPhase::count_edges_over_limit() {
  if (!(settings.strain_limit > 0.0)) return;
  for (int e = 0; e < static_cast<int>(edges_.cols()); ++e) {
    const double rest = edge_rest_length_[e];
    if (!(rest > 0.0)) continue;  // collider edges
    const double length = (x_end_.col(edges_(1, e)) - x_end_.col(edges_(0, e))).norm();
    if (length > over_limit_length(rest, settings.strain_limit)) ++stats_.edges_over_strain_limit;
  }
}

void CollisionPhase::measure_corrections(const std::vector<Cloth>& cloths) {
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshSlot& slot = meshes_[c];
    const Positions& integrated = cloths[c].state.x;
    const double noticeable = 0.01 * slot.thickness;
    for (int i = 0; i < slot.num_vertices; ++i) {
      const double moved = (x_end_.col(slot.offsets.vertex + i) - integrated.col(i)).norm();
      stats_.largest_correction = std::max(stats_.largest_correction, moved);
      if (moved > noticeable) ++stats_.corrected_vertices;
    }
  }
}

void CollisionPhase::scatter_motion(std::vector<Cloth>& cloths) const {
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshSlot& slot = meshes_[c];
    cloths[c].state.x = x_end_.middleCols(slot.offsets.vertex, slot.num_vertices);
    cloths[c].state.v = velocity_.middleCols(slot.offsets.vertex, slot.num_vertices);
  }
}

void CollisionPhase::label_records(size_t first) {
  for (size_t r = first; r < records_.size(); ++r) {
    ContactRecord& record = records_[r];
    int mesh_a, mesh_b;
    if (record.kind == ContactKind::vertex_face) {
      mesh_a = vertex_mesh_[record.primitive_a];
      mesh_b = vertex_mesh_[triangles_(0, record.primitive_b)];
    } else {
      mesh_a = vertex_mesh_[edges_(0, record.primitive_a)];
      mesh_b = vertex_mesh_[edges_(0, record.primitive_b)];
    }
    if (meshes_[mesh_a].soft_body || meshes_[mesh_b].soft_body) {
      record.partners = ContactPartners::soft_body;
    } else if (mesh_a >= num_cloths_ || mesh_b >= num_cloths_) {
      record.partners = ContactPartners::cloth_solid;
    } else {
      record.partners = ContactPartners::cloth_cloth;
    }
  }
}

}  // namespace weft
