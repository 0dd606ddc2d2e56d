#include "collision/impact_zones.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>

namespace weft {

namespace {

// Eigenvalues of the inertia tensor below this fraction of the largest are treated as zero
// (collinear or single-vertex zones): no rotation about those axes is determined.
constexpr double singular_inertia_ratio = 1e-12;

// Gauss-Seidel sweeps of the last-resort pull (pull_free_vertices_to_zones). A sweep in edge order
// carries a correction along a grid's rows in one sweep and across them one ring a sweep, so this
// covers a cloth of up to ~1,000 vertices across; the sweeps stop as soon as every edge is within
// the limit.
constexpr int zone_pull_sweeps = 1024;

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];  // path halving
    v = parent[v];
  }
  return v;
}

void unite(std::vector<int>& parent, int a, int b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

// Angular velocity w = I^+ L, the pseudo-inverse dropping directions of (near) zero inertia.
Vec3 solve_angular_velocity(const Mat3& inertia, const Vec3& angular_momentum) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(inertia);
  const Vec3& values = eigen.eigenvalues();
  const double cutoff = singular_inertia_ratio * values.cwiseAbs().maxCoeff();
  const Vec3 projected = eigen.eigenvectors().transpose() * angular_momentum;
  Vec3 scaled = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    if (values[k] > cutoff && values[k] > 0.0) scaled[k] = projected[k] / values[k];
  }
  return eigen.eigenvectors() * scaled;
}

// Sets the average velocity of vertex v to (target - x_start)/h, keeping velocity in step.
void move_end_to(CollisionStep& step, int v, const Vec3& target) {
  step.velocity.col(v) += (target - step.x_end.col(v)) / step.time_step;
  step.x_end.col(v) = target;
}

void stop_vertex(CollisionStep& step, int v) {
  if (step.inverse_mass[v] > 0.0) move_end_to(step, v, step.x_start.col(v));
}

// The zones' last resort for the strain limit, run when their passes are spent with a motion free
// of collisions and edges still over the limit (the zones grow one ring of vertices a pass
// through them). Every zone vertex is held (infinite mass) and the limiter's Gauss-Seidel sweeps
// pull the free vertices until every edge with a free end is within the limit: each edge's limit
// is a convex set, so the sweeps converge whenever the held vertices leave a motion that meets
// them all. The pulled motion is kept only if it is clean (no collision, no edge over the
// limit); otherwise the motion before it is restored. Returns whether it was kept.
bool pull_free_vertices_to_zones(CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                                 const std::vector<EdgeEdgePair>& edge_edges,
                                 const ResponseSettings& settings, ImpactZoneWorkspace& workspace,
                                 const StrainBound& strain) {
  workspace.saved_x_end = step.x_end;  // same sizes every step: no allocation once grown
  workspace.saved_velocity = step.velocity;
  workspace.held_inverse_mass = step.inverse_mass;
  for (const int v : workspace.members) workspace.held_inverse_mass[v] = 0.0;
  CollisionStep held{step.x_start,   step.x_end, step.velocity,  workspace.held_inverse_mass,
                     step.triangles, step.edges, step.time_step, step.holdable};
  limit_edge_strain(held, strain.rest_length, strain.max_strain, zone_pull_sweeps);

  detect_collisions(step, vertex_faces, edge_edges, settings, workspace.collisions);
  bool clean = workspace.collisions.empty();
  for (int e = 0; clean && e < static_cast<int>(step.edges.cols()); ++e)
    clean = !edge_over_limit(step, strain, e);
  if (!clean) {
    step.x_end = workspace.saved_x_end;
    step.velocity = workspace.saved_velocity;
    workspace.collisions.found.clear();  // the restored motion is the collision-free one before the pull
  }
  return clean;
}

}  // namespace

void apply_rigid_motion(CollisionStep& step, const int* vertices, int count) {
  const double h = step.time_step;

  // Weights: vertex masses, or only the infinite-mass vertices (weight 1) when there are any.
  bool has_infinite = false;
  for (int k = 0; k < count; ++k) has_infinite = has_infinite || step.inverse_mass[vertices[k]] == 0.0;
  const auto weight_of = [&](int v) {
    const double inverse_mass = step.inverse_mass[v];
    if (has_infinite) return inverse_mass == 0.0 ? 1.0 : 0.0;
    return 1.0 / inverse_mass;
  };

  // Centre of mass and its average velocity over the step.
  double total = 0.0;
  Vec3 center = Vec3::Zero();
  Vec3 center_velocity = Vec3::Zero();
  for (int k = 0; k < count; ++k) {
    const int v = vertices[k];
    const double m = weight_of(v);
    total += m;
    center += m * step.x_start.col(v);
    center_velocity += m * (step.x_end.col(v) - step.x_start.col(v));
  }
  center /= total;
  center_velocity /= total * h;

  // Angular momentum L = sum m r x (u - u_c) and inertia I = sum m (|r|^2 1 - r r^T) about it.
  Vec3 angular_momentum = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
  for (int k = 0; k < count; ++k) {
    const int v = vertices[k];
    const double m = weight_of(v);
    const Vec3 r = step.x_start.col(v) - center;
    const Vec3 u = (step.x_end.col(v) - step.x_start.col(v)) / h - center_velocity;
    angular_momentum += m * r.cross(u);
    inertia += m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  const Vec3 omega = solve_angular_velocity(inertia, angular_momentum);

  // End positions of the rigid motion: translate the centre by h u_c and rotate the offsets by
  // h w about it (a rotation, not x + h w x r, so the zone does not stretch).
  const double angle = h * omega.norm();
  const Mat3 rotation =
      angle > 0.0 ? Mat3(Eigen::AngleAxisd(angle, omega.normalized()).toRotationMatrix()) : Mat3::Identity();
  const Vec3 center_end = center + h * center_velocity;
  for (int k = 0; k < count; ++k) {
    const int v = vertices[k];
    if (step.inverse_mass[v] == 0.0) continue;
    move_end_to(step, v, center_end + rotation * (step.x_start.col(v) - center));
  }
}

ImpactZoneResult resolve_impact_zones(CollisionStep& step, const std::vector<VertexFacePair>& vertex_faces,
                                      const std::vector<EdgeEdgePair>& edge_edges,
                                      const ResponseSettings& settings, ImpactZoneWorkspace& workspace,
                                      const StrainBound* strain, const CollisionCandidates* first_pass) {
  const int n = static_cast<int>(step.x_start.cols());
  std::vector<int>& parent = workspace.parent;
  std::vector<int>& members = workspace.members;
  std::vector<char>& in_zone = workspace.in_zone;
  CcdCollisions& collisions = workspace.collisions;
  std::vector<int>& stretched = workspace.stretched;
  parent.resize(n);
  std::iota(parent.begin(), parent.end(), 0);
  in_zone.assign(n, 0);
  members.clear();
  members.reserve(n);  // once: a zone larger than any before must not allocate in a steady step

  const auto join = [&](int a, int b) {
    unite(parent, a, b);
    for (const int v : {a, b}) {
      if (!in_zone[v]) {
        in_zone[v] = 1;
        members.push_back(v);
      }
    }
  };
  const auto find_stretched = [&] {
    stretched.clear();
    if (strain == nullptr) return;
    stretched.reserve(step.edges.cols());  // once: steady steps allocate nothing
    for (int e = 0; e < static_cast<int>(step.edges.cols()); ++e) {
      if (edge_over_limit(step, *strain, e)) stretched.push_back(e);
    }
  };

  ImpactZoneResult result;
  // Detection over the candidates; until a zone pass has moved anything, over `first_pass` when
  // given (the caller's pairs that may collide on the motion as it came in).
  const auto detect = [&] {
    const bool as_given = result.passes == 0 && first_pass != nullptr;
    detect_collisions(step, as_given ? first_pass->vertex_face : vertex_faces,
                      as_given ? first_pass->edge_edge : edge_edges, settings, collisions);
  };
  for (; result.passes < settings.max_impact_zone_passes; ++result.passes) {
    detect();
    find_stretched();
    if (collisions.empty() && stretched.empty()) {
      result.clean = true;
      break;
    }

    // Merge the vertices of every remaining collision into one zone (BFA 2002 section 7.4), and
    // the ends of every edge over the strain limit.
    for (const CcdCollision& collision : collisions.found) {
      const std::array<int, 4>& vertices = collision.stencil.vertices;
      for (int k = 0; k < 4; ++k) join(vertices[0], vertices[k]);
    }
    for (const int e : stretched) join(step.edges(0, e), step.edges(1, e));

    // Group the zone vertices by root, then give each zone one rigid motion.
    std::sort(members.begin(), members.end(), [&](int a, int b) {
      const int root_a = find_root(parent, a);
      const int root_b = find_root(parent, b);
      return root_a != root_b ? root_a < root_b : a < b;
    });
    for (size_t begin = 0; begin < members.size();) {
      const int root = find_root(parent, members[begin]);
      size_t end = begin + 1;
      while (end < members.size() && find_root(parent, members[end]) == root) ++end;
      apply_rigid_motion(step, members.data() + begin, static_cast<int>(end - begin));
      begin = end;
    }
  }

  // Fail-safe of the fail-safe. A motion the last pass left free of collisions, with only edges
  // over the strain limit, first has its free vertices pulled to the zones (below). If that is
  // not clean, the motion before the pull is kept: the edges left over it are held by a zone
  // whose pins move non-rigidly (a fixed and a turning edge), and stopping the zone would let the
  // pins stretch them further. A motion with collisions stops the zones, then everything of
  // finite mass.
  if (!result.clean) {
    detect();
    find_stretched();
    result.clean = collisions.empty() && stretched.empty();
    if (!result.clean && collisions.empty() && strain != nullptr) {
      result.pulled =
          pull_free_vertices_to_zones(step, vertex_faces, edge_edges, settings, workspace, *strain);
      if (result.pulled) {
        result.clean = true;
        stretched.clear();
      }
    }
  }
  if (!result.clean && !collisions.empty()) {
    result.stopped = true;
    for (int v : members) stop_vertex(step, v);
    detect();
    find_stretched();
    if (!collisions.empty() || !stretched.empty()) {
      for (int v = 0; v < n; ++v) stop_vertex(step, v);
      detect_collisions(step, vertex_faces, edge_edges, settings, collisions);
      find_stretched();
    }
    // Still colliding with everything of finite mass at its start: pins are driving cloth through
    // cloth (a zone holding a fixed and a turning pinned edge, which no rigid motion follows).
    // Holding them too restores the start, which had no intersection; their script lags a step.
    if (!collisions.empty() && step.holdable != nullptr) {
      for (int v = 0; v < n; ++v) {
        if (step.inverse_mass[v] == 0.0 && (*step.holdable)[v] && step.x_end.col(v) != step.x_start.col(v)) {
          move_end_to(step, v, step.x_start.col(v));
          ++result.held;
        }
      }
      if (result.held > 0) {
        detect_collisions(step, vertex_faces, edge_edges, settings, collisions);
        find_stretched();
      }
    }
    result.clean = collisions.empty() && stretched.empty();
  }

  result.collision_free = collisions.empty();  // every path above ends on a detection of the final motion

  // Zone statistics.
  for (size_t k = 0; k < members.size(); ++k) {
    if (k == 0 || find_root(parent, members[k]) != find_root(parent, members[k - 1])) ++result.zones;
  }
  result.zone_vertices = static_cast<int>(members.size());
  return result;
}

}  // namespace weft
