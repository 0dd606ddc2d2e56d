#include "sim/barrier_contact.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"
#include "physics/contact_barrier.hpp"

namespace weft {

void BarrierContact::set_meshes(const std::vector<BarrierMesh>& meshes, const std::vector<Collider>& analytic,
                                const std::vector<BarrierBall>& balls) {
  analytic_ = analytic;
  balls_ = balls;
  ball_colliders_.clear();
  for (const BarrierBall& ball : balls) {
    ball_colliders_.push_back(static_cast<int>(analytic_.size()));
    Collider sphere;
    sphere.shape = ColliderShape::sphere;
    sphere.center = ball.center;
    sphere.radius = ball.vertex_radius;
    sphere.friction = ball.friction;
    analytic_.push_back(sphere);
  }
  slots_.clear();
  slots_.resize(meshes.size());
  num_cloths_ = 0;
  MeshIndexOffsets offsets;
  for (size_t m = 0; m < meshes.size(); ++m) {
    Slot& slot = slots_[m];
    slot.mesh = meshes[m];
    if (slot.mesh.is_cloth) num_cloths_ = static_cast<int>(m) + 1;
    const int num_vertices = static_cast<int>(slot.mesh.positions.cols());
    slot.topology = build_topology(slot.mesh.triangles, num_vertices);
    slot.offsets = offsets;
    slot.global_triangles = slot.mesh.triangles.array() + offsets.vertex;
    slot.vertex_entries = point_entries(offsets.vertex, num_vertices);
    slot.edge_entries = segment_entries(slot.topology.edges, offsets.vertex);
    offsets = next_offsets(offsets, num_vertices, static_cast<int>(slot.mesh.triangles.cols()),
                           slot.topology.num_edges());
  }
  from_.resize(3, offsets.vertex);
  to_.resize(3, offsets.vertex);
  start_.resize(3, offsets.vertex);
  vertex_mesh_.assign(offsets.vertex, 0);
  edges_.resize(2, offsets.edge);
  for (size_t m = 0; m < slots_.size(); ++m) {
    Slot& slot = slots_[m];
    const int n = static_cast<int>(slot.mesh.positions.cols());
    from_.middleCols(slot.offsets.vertex, n) = slot.mesh.positions;
    to_.middleCols(slot.offsets.vertex, n) = slot.mesh.positions;
    start_.middleCols(slot.offsets.vertex, n) = slot.mesh.positions;
    for (int v = 0; v < n; ++v) vertex_mesh_[slot.offsets.vertex + v] = static_cast<int>(m);
    edges_.middleCols(slot.offsets.edge, slot.topology.num_edges()) =
        slot.topology.edges.array() + slot.offsets.vertex;
  }
  caches_.assign(num_cloths_, CandidateCache{});
  for (CandidateCache& cache : caches_) {
    cache.lower = from_;
    cache.upper = from_;
  }
  cloth_ = -1;
  stencils_ = nullptr;
}

PrimitiveMesh BarrierContact::primitive_mesh(const Slot& slot) const {
  return PrimitiveMesh{slot.mesh.triangles, slot.topology, slot.offsets, slot.bvh,
                       slot.vertex_bvh,     slot.edge_bvh};
}

double BarrierContact::pair_radius(const Stencil& stencil) const {
  if (settings.contact_radius > 0.0) return settings.contact_radius;
  double radius = 0.0;
  for (const int v : stencil.vertices) radius = std::max(radius, slots_[vertex_mesh_[v]].mesh.thickness);
  return radius;
}

double BarrierContact::contact_radius() const {
  double radius = settings.contact_radius;
  if (!(radius > 0.0)) {
    for (const Slot& s : slots_) radius = std::max(radius, s.mesh.thickness);
  }
  return radius;
}

void BarrierContact::update_hierarchies(Slot& slot, const Positions& from, const Positions& to) {
  // Boxes inflated by half the largest radius: two entries' boxes overlap when their primitives
  // come within it (primitive_queries.hpp).
  const double margin = 0.5 * contact_radius();
  const auto update = [&](Bvh& bvh, const Triangles& entries) {
    if (!slot.built || bvh.needs_rebuild()) {
      bvh.build(from, to, entries, margin);
    } else {
      bvh.refit(from, to, margin);
    }
  };
  update(slot.bvh, slot.global_triangles);
  update(slot.vertex_bvh, slot.vertex_entries);
  update(slot.edge_bvh, slot.edge_entries);
  slot.built = true;
}

void BarrierContact::prepare_cloth(int cloth, const std::vector<const Positions*>& current,
                                   const std::vector<const Positions*>& step_start,
                                   const Eigen::VectorXd& inverse_mass, double mean_mass) {
  cloth_ = cloth;
  inverse_mass_ = inverse_mass;
  mean_mass_ = mean_mass;
  for (int c = 0; c < num_cloths_; ++c) {
    Slot& slot = slots_[c];
    const int n = static_cast<int>(slot.mesh.positions.cols());
    from_.middleCols(slot.offsets.vertex, n) = *current[c];
    to_.middleCols(slot.offsets.vertex, n) = *current[c];
    start_.middleCols(slot.offsets.vertex, n) = *step_start[c];
  }
  // Colliders are static: their hierarchies are built once. The cloths' are built by search().
  for (Slot& slot : slots_) {
    if (!slot.mesh.is_cloth && !slot.built) update_hierarchies(slot, from_, from_);
  }
  stencils_ = &caches_[cloth].stencils;
  cloth_triangles_ = &slots_[cloth].mesh.triangles;
}

int BarrierContact::local(int combined) const {
  const Slot& slot = slots_[cloth_];
  const int v = combined - slot.offsets.vertex;
  return v >= 0 && v < slot.mesh.positions.cols() ? v : -1;
}

Vec3 BarrierContact::position(int combined, const Positions& x) const {
  const int v = local(combined);
  return v >= 0 ? Vec3(x.col(v)) : Vec3(from_.col(combined));
}

BarrierContact::Stencil BarrierContact::stencil(const VertexFacePair& pair) const {
  const int triangle = pair.triangle;
  // The triangle's mesh: the one whose triangle range holds it.
  int mesh = 0;
  while (mesh + 1 < static_cast<int>(slots_.size()) && slots_[mesh + 1].offsets.triangle <= triangle) ++mesh;
  const auto corners = slots_[mesh].global_triangles.col(triangle - slots_[mesh].offsets.triangle);
  return Stencil{{pair.vertex, corners[0], corners[1], corners[2]}, false};
}

BarrierContact::Stencil BarrierContact::stencil(const EdgeEdgePair& pair) const {
  return Stencil{
      {edges_(0, pair.edge_a), edges_(1, pair.edge_a), edges_(0, pair.edge_b), edges_(1, pair.edge_b)}, true};
}

bool BarrierContact::has_free_vertex(const Stencil& stencil) const {
  for (const int v : stencil.vertices) {
    const int l = local(v);
    if (l >= 0 && inverse_mass_[l] > 0.0) return true;
  }
  return false;
}

double BarrierContact::pair_friction(const Stencil& stencil) const {
  const int a = vertex_mesh_[stencil.vertices[0]];
  const int b = vertex_mesh_[stencil.vertices[stencil.edge_edge ? 2 : 1]];
  const BarrierMesh& first = slots_[a].mesh;
  const BarrierMesh& second = slots_[b].mesh;
  if (!first.is_cloth) return first.friction;
  if (!second.is_cloth) return second.friction;
  return 0.5 * (first.friction + second.friction);
}

namespace {

// A lower bound on the distance between a pair's two primitives (vertices 0 or 0-1 against 1-3
// or 2-3): the gap between their bounding boxes along the axis where it is widest.
double box_gap(const std::array<Vec3, 4>& p, bool edge_edge) {
  const int split = edge_edge ? 2 : 1;
  Vec3 a_low = p[0], a_high = p[0], b_low = p[3], b_high = p[3];
  for (int k = 1; k < split; ++k) {
    a_low = a_low.cwiseMin(p[k]);
    a_high = a_high.cwiseMax(p[k]);
  }
  for (int k = split; k < 3; ++k) {
    b_low = b_low.cwiseMin(p[k]);
    b_high = b_high.cwiseMax(p[k]);
  }
  return std::max((a_low - b_high).maxCoeff(), (b_low - a_high).maxCoeff());
}

}  // namespace

BarrierContact::PairGeometry BarrierContact::geometry(const Stencil& stencil, const Positions& x) const {
  const Vec3 p0 = position(stencil.vertices[0], x), p1 = position(stencil.vertices[1], x);
  const Vec3 p2 = position(stencil.vertices[2], x), p3 = position(stencil.vertices[3], x);
  PairGeometry g;
  // Pairs farther apart than the contact radius add nothing: their distance is not needed.
  if (box_gap({p0, p1, p2, p3}, stencil.edge_edge) >= pair_radius(stencil)) {
    g.distance = std::numeric_limits<double>::infinity();
    return g;
  }
  Vec3 offset;
  if (stencil.edge_edge) {
    const EdgeEdgeClosest closest = edge_edge_closest(p0, p1, p2, p3);
    offset = closest.point_a - closest.point_b;
    g.weights = {1.0 - closest.s, closest.s, -(1.0 - closest.t), -closest.t};
  } else {
    const PointTriangleClosest closest = point_triangle_closest(p0, p1, p2, p3);
    offset = p0 - closest.closest;
    g.weights = {1.0, -closest.barycentric[0], -closest.barycentric[1], -closest.barycentric[2]};
  }
  g.distance = offset.norm();
  g.normal = g.distance > 0.0 ? Vec3(offset / g.distance) : Vec3::UnitY();
  return g;
}

namespace {

// Conservative advancement over t in [0, 1]: distance(t) falls at most at the rate lp, so
// advancing by (d - target) / lp keeps it above target = min_separation distance(0); repeated
// from each new distance until the segment's end (1) or until the advances become negligible
// (the t reached). A start at or below zero distance returns 0. A line search needs a safe
// bound, not the earliest time within a distance that the continuous tests' search pins down
// (earliest_proximity, collision/coplanarity_cubic.hpp): stopping once the advances are
// negligible, and at the end without evaluating there, makes this one cheaper.
template <class Distance>
double advance_conservatively(const Distance& distance, double d0, double lp, double min_separation) {
  if (!(lp > 0.0)) return 1.0;
  const double target = min_separation * d0;
  double t = 0.0, d = d0;
  for (int iteration = 0; iteration < 64; ++iteration) {
    const double advance = (d - target) / lp;
    if (t + advance >= 1.0) return 1.0;
    if (advance < 1e-6) break;
    t += advance;
    d = distance(t);
  }
  return t;
}

}  // namespace

// A pair along the segment from_ -> to_: its distance falls at most at the rate of its vertices'
// largest relative displacement l_p (after Li et al. 2021, additive CCD), so it stays out of
// the contact radius along the segment where its start's distance less l_p is outside.
BarrierContact::PairAdvance BarrierContact::advance(const Stencil& stencil) const {
  std::array<Vec3, 4> p, q;
  Vec3 mean = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    p[k] = from_.col(stencil.vertices[k]);
    q[k] = to_.col(stencil.vertices[k]) - p[k];
    mean += 0.25 * q[k];
  }
  for (Vec3& d : q) d -= mean;
  const double lp = stencil.edge_edge
                        ? std::max(q[0].norm(), q[1].norm()) + std::max(q[2].norm(), q[3].norm())
                        : q[0].norm() + std::max({q[1].norm(), q[2].norm(), q[3].norm()});
  // The box gap bounds the start's distance from below: a pair that cannot come within the
  // radius, or cannot close its share 1 - min_separation of the gap, needs no distance.
  const double radius = pair_radius(stencil);
  const double gap = box_gap(p, stencil.edge_edge);
  if (gap - lp >= radius) return {1.0, false};
  if ((1.0 - settings.min_separation) * gap >= lp) return {1.0, true};
  const auto distance = [&](double t) {
    const Vec3 a = p[0] + t * q[0], b = p[1] + t * q[1], c = p[2] + t * q[2], d = p[3] + t * q[3];
    return stencil.edge_edge ? edge_edge_closest(a, b, c, d).distance
                             : point_triangle_closest(a, b, c, d).distance;
  };
  const double d0 = distance(0.0);
  return {advance_conservatively(distance, d0, lp, settings.min_separation), d0 - lp < radius};
}

// A vertex against a collider's signed distance, which changes at most as fast as the vertex moves.
double BarrierContact::advance(const SolidPair& pair, const Positions& x,
                               const Eigen::Ref<const Positions>& dx) const {
  const Collider& collider = analytic_[pair.collider];
  const Vec3 p = x.col(pair.vertex), q = dx.col(pair.vertex);
  const auto distance = [&](double t) {
    Vec3 normal;
    return signed_distance(collider, p + t * q, normal);
  };
  return advance_conservatively(distance, distance(0.0), q.norm(), settings.min_separation);
}

bool BarrierContact::covered() const {
  const CandidateCache& cache = caches_[cloth_];
  if (!cache.valid) return false;
  // The other cloths hold still in this solve (from_ == to_ there).
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshIndexOffsets& offsets = slots_[c].offsets;
    const int n = static_cast<int>(slots_[c].mesh.positions.cols());
    const auto lower = cache.lower.middleCols(offsets.vertex, n);
    const auto upper = cache.upper.middleCols(offsets.vertex, n);
    const auto from = from_.middleCols(offsets.vertex, n);
    const auto to = to_.middleCols(offsets.vertex, n);
    if ((from.array() < lower.array()).any() || (from.array() > upper.array()).any() ||
        (to.array() < lower.array()).any() || (to.array() > upper.array()).any())
      return false;
  }
  return true;
}

void BarrierContact::search() {
  CandidateCache& cache = caches_[cloth_];
  const double radius = contact_radius();
  const double margin = settings.reuse_margin_ratio * radius;
  for (int c = 0; c < num_cloths_; ++c) {
    const MeshIndexOffsets& offsets = slots_[c].offsets;
    const int n = static_cast<int>(slots_[c].mesh.positions.cols());
    cache.lower.middleCols(offsets.vertex, n) =
        (from_.middleCols(offsets.vertex, n).cwiseMin(to_.middleCols(offsets.vertex, n))).array() - margin;
    cache.upper.middleCols(offsets.vertex, n) =
        (from_.middleCols(offsets.vertex, n).cwiseMax(to_.middleCols(offsets.vertex, n))).array() + margin;
  }
  // Every cloth's hierarchies over these boxes (a hierarchy boxes each entry over both arguments).
  for (int c = 0; c < num_cloths_; ++c) update_hierarchies(slots_[c], cache.lower, cache.upper);
  const SweptVertexBoxes boxes{cache.lower, cache.upper, radius};
  Slot& slot = slots_[cloth_];
  candidates_.clear();
  if (slot.mesh.self_collision)
    append_self_primitive_candidates(primitive_mesh(slot), boxes, buffers_, candidates_);
  for (size_t m = 0; m < slots_.size(); ++m) {
    if (static_cast<int>(m) == cloth_) continue;
    append_primitive_candidates_between(primitive_mesh(slot), primitive_mesh(slots_[m]), boxes, buffers_,
                                        candidates_);
  }
  sort_candidates(candidates_);
  cache.stencils.clear();
  for (const VertexFacePair& pair : candidates_.vertex_face) {
    const Stencil s = stencil(pair);
    if (has_free_vertex(s)) cache.stencils.push_back(s);
  }
  for (const EdgeEdgePair& pair : candidates_.edge_edge) {
    const Stencil s = stencil(pair);
    if (has_free_vertex(s)) cache.stencils.push_back(s);
  }
  cache.valid = true;
  report_.vertex_face_candidates = static_cast<int>(candidates_.vertex_face.size());
  report_.edge_edge_candidates = static_cast<int>(candidates_.edge_edge.size());
}

// A triangle's distance from a fixed point changes at most as fast as its fastest vertex moves.
// Triangles starting inside a ball (placed so: the scene's push-out moves them) bound nothing.
double BarrierContact::advance_balls(const Positions& x, const Eigen::Ref<const Positions>& dx) {
  if (balls_.empty()) return 1.0;
  const Triangles& triangles = *cloth_triangles_;
  const int num_balls = static_cast<int>(balls_.size());
  const int count = static_cast<int>(triangles.cols()) * num_balls;
  double alpha = 1.0;
#pragma omp parallel for schedule(static) reduction(min : alpha) if (count > 1024)
  for (int i = 0; i < count; ++i) {
    const int t = i / num_balls;
    const BarrierBall& ball = balls_[i % num_balls];
    std::array<Vec3, 3> p, q;
    bool free = false;
    double lp = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int v = triangles(k, t);
      free = free || inverse_mass_[v] > 0.0;
      p[k] = x.col(v);
      q[k] = dx.col(v);
      lp = std::max(lp, q[k].norm());
    }
    if (!free) continue;
    // A lower bound on the distance first: the centroid's less the farthest corner's offset.
    const Vec3 centroid = (p[0] + p[1] + p[2]) / 3.0;
    const double reach =
        std::max({(p[0] - centroid).norm(), (p[1] - centroid).norm(), (p[2] - centroid).norm()});
    const double lower = (centroid - ball.center).norm() - reach - ball.radius;
    if ((1.0 - settings.min_separation) * lower >= lp) continue;
    const auto distance = [&](double s) {
      return point_triangle_closest(ball.center, p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2]).distance -
             ball.radius;
    };
    const double d0 = distance(0.0);
    if (!(d0 > 0.0) || (1.0 - settings.min_separation) * d0 >= lp) continue;
    alpha = std::min(alpha, advance_conservatively(distance, d0, lp, settings.min_separation));
  }
  return alpha;
}

double BarrierContact::max_step(const Positions& x, const Eigen::Ref<const Positions>& dx) {
  const int n = static_cast<int>(x.cols());
  const int offset = slots_[cloth_].offsets.vertex;
  from_.middleCols(offset, n) = x;
  to_.middleCols(offset, n) = x + dx;
  if (!covered()) search();
  const double radius = contact_radius();
  // Vertices that can come within the radius of an analytic collider along the segment.
  solid_pairs_.clear();
  for (int k = 0; k < static_cast<int>(analytic_.size()); ++k) {
    for (int v = 0; v < n; ++v) {
      if (!(inverse_mass_[v] > 0.0)) continue;
      Vec3 normal;
      const double d = signed_distance(analytic_[k], x.col(v), normal);
      if (d < radius + dx.col(v).norm()) solid_pairs_.push_back({v, k});
    }
  }
  double alpha = 1.0;
  const std::vector<Stencil>& stencils = *stencils_;
  const int count = static_cast<int>(stencils.size());
  near_.resize(stencils.size());
#pragma omp parallel for schedule(static) reduction(min : alpha) if (count > 256)
  for (int i = 0; i < count; ++i) {
    const PairAdvance a = advance(stencils[i]);
    alpha = std::min(alpha, a.alpha);
    near_[i] = a.near ? 1 : 0;
  }
  active_.clear();
  for (int i = 0; i < count; ++i) {
    if (near_[i]) active_.push_back(stencils[i]);
  }
  const int solids = static_cast<int>(solid_pairs_.size());
#pragma omp parallel for schedule(static) reduction(min : alpha) if (solids > 256)
  for (int i = 0; i < solids; ++i) alpha = std::min(alpha, advance(solid_pairs_[i], x, dx));
  return std::min(alpha, advance_balls(x, dx));
}

double BarrierContact::begin_step(const Positions& x_start, const Positions& predictor, double h) {
  report_ = SolveContactReport{};
  kappa_ = settings.stiffness_ratio * mean_mass_ / (h * h);
  epsilon_ = settings.slip_speed * h;
  // The pairs along the predictor hold every pair within the radius at x_start (the segment's
  // start): those in contact there keep their normal force, normal and weights for the step.
  const double alpha = max_step(x_start, predictor);
  friction_.clear();
  for (const Stencil& s : active_) {
    const PairGeometry g = geometry(s, x_start);
    const double radius = pair_radius(s);
    const double mu = pair_friction(s);
    if (!(g.distance < radius) || !(mu > 0.0)) continue;
    const double force = -kappa_ * log_barrier(g.distance, radius).first;
    if (!(force > 0.0)) continue;
    FrictionPair f;
    f.tangent = Mat3::Identity() - g.normal * g.normal.transpose();
    f.fixed_slip.setZero();
    for (int k = 0; k < 4; ++k) {
      const int v = local(s.vertices[k]);
      f.vertices[k] = v;
      f.weights[k] = g.weights[k];
      if (v < 0) f.fixed_slip += g.weights[k] * (from_.col(s.vertices[k]) - start_.col(s.vertices[k]));
    }
    f.fixed_slip = f.tangent * f.fixed_slip;
    f.coefficient = mu * force;
    friction_.push_back(f);
  }
  const double radius = contact_radius();
  for (const SolidPair& pair : solid_pairs_) {
    const Collider& collider = analytic_[pair.collider];
    Vec3 normal;
    const double d = signed_distance(collider, x_start.col(pair.vertex), normal);
    if (!(d < radius) || !(collider.friction > 0.0)) continue;
    const double force = -kappa_ * log_barrier(d, radius).first;
    if (!(force > 0.0)) continue;
    FrictionPair f;
    f.vertices = {pair.vertex, -1, -1, -1};
    f.weights = {1.0, 0.0, 0.0, 0.0};
    f.tangent = Mat3::Identity() - normal * normal.transpose();
    f.fixed_slip.setZero();
    f.coefficient = collider.friction * force;
    friction_.push_back(f);
  }
  x_step_start_ = x_start;
  return alpha;
}

double BarrierContact::evaluate(const Positions& x, Positions* gradient, ContactBlocks* blocks) {
  ContactSums sums;
  const double value = evaluate_contacts(x, nullptr, gradient, blocks, sums);
  if (std::isfinite(value)) {
    last_potential_ = sums.barrier;
    report_.pairs = sums.pairs;
  }
  return value;
}

double BarrierContact::evaluate_moving(const Positions& x, const std::vector<char>& moving,
                                       Positions* gradient, ContactBlocks* blocks) {
  ContactSums sums;
  return evaluate_contacts(x, &moving, gradient, blocks, sums);
}

bool BarrierContact::touches(const Stencil& stencil, const std::vector<char>& moving) const {
  for (const int combined : stencil.vertices) {
    const int v = local(combined);
    if (v >= 0 && moving[v]) return true;
  }
  return false;
}

bool BarrierContact::touches(const FrictionPair& pair, const std::vector<char>& moving) {
  for (const int v : pair.vertices) {
    if (v >= 0 && moving[v]) return true;
  }
  return false;
}

double BarrierContact::evaluate_contacts(const Positions& x, const std::vector<char>* moving,
                                         Positions* gradient, ContactBlocks* blocks, ContactSums& sums) {
  if (blocks != nullptr) blocks->clear();
  const std::vector<Stencil>& stencils = active_;
  selected_.clear();
  for (int i = 0; i < static_cast<int>(stencils.size()); ++i) {
    if (moving == nullptr || touches(stencils[i], *moving)) selected_.push_back(i);
  }
  const int count = static_cast<int>(selected_.size());
  geometry_.resize(selected_.size());
#pragma omp parallel for schedule(static) if (count > 256)
  for (int i = 0; i < count; ++i) geometry_[i] = geometry(stencils[selected_[i]], x);
  double barrier = 0.0;
  int pairs = 0;
  for (int i = 0; i < count; ++i) {
    const Stencil& s = stencils[selected_[i]];
    const PairGeometry& g = geometry_[i];
    const double radius = pair_radius(s);
    if (!(g.distance < radius)) continue;
    if (!(g.distance > 0.0)) return std::numeric_limits<double>::infinity();
    const BarrierValue b = log_barrier(g.distance, radius);
    barrier += kappa_ * b.value;
    ++pairs;
    std::array<int, 4> vertices;
    for (int k = 0; k < 4; ++k) vertices[k] = local(s.vertices[k]);
    if (gradient != nullptr) {
      for (int k = 0; k < 4; ++k) {
        if (vertices[k] >= 0) gradient->col(vertices[k]) += (kappa_ * b.first * g.weights[k]) * g.normal;
      }
    }
    if (blocks != nullptr) {
      blocks->vertices.push_back(vertices);
      blocks->weights.push_back(g.weights);
      blocks->blocks.push_back((kappa_ * b.second) * g.normal * g.normal.transpose());
    }
  }
  // Cloth vertices against analytic colliders: one vertex each, so diagonal blocks only.
  selected_solids_.clear();
  for (int i = 0; i < static_cast<int>(solid_pairs_.size()); ++i) {
    if (moving == nullptr || (*moving)[solid_pairs_[i].vertex]) selected_solids_.push_back(i);
  }
  const int solids = static_cast<int>(selected_solids_.size());
  solid_distance_.resize(selected_solids_.size());
  solid_normal_.resize(selected_solids_.size());
#pragma omp parallel for schedule(static) if (solids > 256)
  for (int i = 0; i < solids; ++i) {
    const SolidPair& pair = solid_pairs_[selected_solids_[i]];
    solid_distance_[i] = signed_distance(analytic_[pair.collider], x.col(pair.vertex), solid_normal_[i]);
  }
  const double radius = contact_radius();
  for (int i = 0; i < solids; ++i) {
    const double d = solid_distance_[i];
    if (!(d < radius)) continue;
    if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
    const BarrierValue b = log_barrier(d, radius);
    const Vec3& normal = solid_normal_[i];
    const int v = solid_pairs_[selected_solids_[i]].vertex;
    barrier += kappa_ * b.value;
    ++pairs;
    if (gradient != nullptr) gradient->col(v) += (kappa_ * b.first) * normal;
    if (blocks != nullptr) {
      blocks->vertices.push_back({v, -1, -1, -1});
      blocks->weights.push_back({1.0, 0.0, 0.0, 0.0});
      blocks->blocks.push_back((kappa_ * b.second) * normal * normal.transpose());
    }
  }
  sums.barrier = barrier;
  sums.pairs = pairs;
  // Lagged friction: mu lambda f0(|u|) on the tangential displacement u since the step's start.
  double friction = 0.0;
  for (const FrictionPair& f : friction_) {
    if (moving != nullptr && !touches(f, *moving)) continue;
    Vec3 slip = f.fixed_slip;
    for (int k = 0; k < 4; ++k) {
      const int v = f.vertices[k];
      if (v >= 0) slip += f.weights[k] * (f.tangent * (x.col(v) - x_step_start_.col(v)));
    }
    const double y = slip.norm();
    const FrictionValue value = smoothed_friction(y, epsilon_);
    friction += f.coefficient * value.value;
    if (gradient != nullptr && y > 0.0) {
      const Vec3 force = (f.coefficient * value.ratio) * slip;  // mu lambda f1(y) u / y
      for (int k = 0; k < 4; ++k) {
        if (f.vertices[k] >= 0) gradient->col(f.vertices[k]) += f.weights[k] * (f.tangent * force);
      }
    }
    if (blocks != nullptr) {
      Mat3 block = (f.coefficient * value.ratio) * f.tangent;
      if (y > 0.0) {
        const Vec3 direction = slip / y;
        block += (f.coefficient * (value.second - value.ratio)) * direction * direction.transpose();
      }
      blocks->vertices.push_back(f.vertices);
      blocks->weights.push_back(f.weights);
      blocks->blocks.push_back(f.tangent * block * f.tangent);
    }
  }
  return barrier + friction;
}

}  // namespace weft
