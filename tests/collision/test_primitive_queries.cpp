// The primitive-level broad phase against a brute-force reference over every vertex-face and
// edge-edge pair (written here, apart from the queries' own filters), on random meshes, within
// one mesh and between two; its culling against the triangle-pair query it replaces; the
// re-query around moved vertices; the same lists on any number of threads; and small cases
// (a hinge folded flat, a flat grid at rest, a non-manifold fin).
#include "collision/primitive_queries.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"
#include "collision/self_culling.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

// One mesh of a test world: its topology, offsets and three hierarchies over the world's
// vertex boxes (lower, upper), inflated by gap / 2 as the collision phase builds them.
struct QueryMesh {
  Triangles triangles;
  MeshTopology topology;
  MeshIndexOffsets offsets;
  int num_vertices = 0;
  Bvh triangle_bvh, vertex_bvh, edge_bvh;

  void build(const Positions& lower, const Positions& upper, double gap) {
    const Triangles global = triangles.array() + offsets.vertex;
    triangle_bvh.build(lower, upper, global, 0.5 * gap);
    vertex_bvh.build(lower, upper, point_entries(offsets.vertex, num_vertices), 0.5 * gap);
    edge_bvh.build(lower, upper, segment_entries(topology.edges, offsets.vertex), 0.5 * gap);
  }
  void refit(const Positions& lower, const Positions& upper, double gap) {
    triangle_bvh.refit(lower, upper, 0.5 * gap);
    vertex_bvh.refit(lower, upper, 0.5 * gap);
    edge_bvh.refit(lower, upper, 0.5 * gap);
  }
  PrimitiveMesh view() const {
    return PrimitiveMesh{triangles, topology, offsets, triangle_bvh, vertex_bvh, edge_bvh};
  }
};

// Meshes laid out one after the other in the combined index spaces, with per-vertex boxes.
struct QueryWorld {
  double gap = 0.02;
  std::vector<QueryMesh> meshes;
  Positions lower, upper;  // (3 x n_vertices)

  void add(const Triangles& triangles, int num_vertices) {
    QueryMesh mesh;
    mesh.triangles = triangles;
    mesh.topology = build_topology(triangles, num_vertices);
    mesh.num_vertices = num_vertices;
    if (!meshes.empty()) {
      const QueryMesh& last = meshes.back();
      mesh.offsets = next_offsets(last.offsets, last.num_vertices, static_cast<int>(last.triangles.cols()),
                                  last.topology.num_edges());
    }
    meshes.push_back(std::move(mesh));
  }
  void build() {
    for (QueryMesh& mesh : meshes) mesh.build(lower, upper, gap);
  }
  SweptVertexBoxes boxes() const { return SweptVertexBoxes{lower, upper, gap}; }
  // Mesh 0 against itself and against every other mesh, as the collision phase queries a cloth.
  CollisionCandidates query() const {
    BvhQueryBuffers buffers;
    CollisionCandidates candidates;
    append_self_primitive_candidates(meshes[0].view(), boxes(), buffers, candidates);
    for (size_t m = 1; m < meshes.size(); ++m) {
      append_primitive_candidates_between(meshes[0].view(), meshes[m].view(), boxes(), buffers, candidates);
    }
    sort_candidates(candidates);
    return candidates;
  }
};

// A mesh moving from x_start to x_end: boxes of its vertices appended to the world's.
void add_swept(QueryWorld& world, const Triangles& triangles, const Positions& x_start,
               const Positions& x_end) {
  const Eigen::Index before = world.lower.cols(), n = x_start.cols();
  world.lower.conservativeResize(3, before + n);
  world.upper.conservativeResize(3, before + n);
  world.lower.rightCols(n) = x_start.cwiseMin(x_end);
  world.upper.rightCols(n) = x_start.cwiseMax(x_end);
  world.add(triangles, static_cast<int>(n));
}

// Three draws, z first, then y, then x: written out because the order in which a call's arguments
// are evaluated is unspecified (g++ goes right to left, clang left to right), so
// Vec3(noise(rng), noise(rng), noise(rng)) gave the two compilers different meshes. This order is
// g++'s, which the thresholds below were set with.
Vec3 random_vec3(std::uniform_real_distribution<double>& noise, std::mt19937& rng) {
  const double z = noise(rng);
  const double y = noise(rng);
  const double x = noise(rng);
  return Vec3(x, y, z);
}

// A grid crumpled by a sine and noise, moving a random step: boxes of its vertices.
void add_swept_grid(QueryWorld& world, int n, unsigned seed, const Vec3& shift,
                    GridTriangulation triangulation) {
  const TriangleMesh grid = make_grid(n, n, 1.0, 1.0, triangulation);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.03, 0.03);
  Positions x_start = grid.positions, x_end;
  for (int v = 0; v < grid.num_vertices(); ++v) {
    x_start(2, v) = 0.15 * std::sin(9.0 * x_start(0, v)) + noise(rng);
    x_start.col(v) += shift;
  }
  x_end = x_start;
  for (int v = 0; v < grid.num_vertices(); ++v) x_end.col(v) += random_vec3(noise, rng);
  add_swept(world, grid.triangles, x_start, x_end);
}

// ---- The reference: every pair, tested one by one -----------------------------------------

struct VertexBox {
  Vec3 lower, upper;
};

VertexBox box_over(const QueryWorld& world, std::initializer_list<int> vertices) {
  VertexBox box{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const int v : vertices) {
    for (int d = 0; d < 3; ++d) {
      box.lower[d] = std::min(box.lower[d], world.lower(d, v));
      box.upper[d] = std::max(box.upper[d], world.upper(d, v));
    }
  }
  return box;
}

// Within the gap along x, y and z.
bool boxes_within_gap(const VertexBox& a, const VertexBox& b, double gap) {
  for (int d = 0; d < 3; ++d) {
    if (a.lower[d] > b.upper[d] + gap || b.lower[d] > a.upper[d] + gap) return false;
  }
  return true;
}

// Each vertex box projected on the unit axis n as centre +- half-extent; the two primitives are
// apart along n when the gap between their projections exceeds gap |n|_1.
bool apart_along(const QueryWorld& world, std::initializer_list<int> from, std::initializer_list<int> to,
                 const Vec3& n) {
  const auto projection = [&](int v) {
    const Vec3 centre = 0.5 * (world.lower.col(v) + world.upper.col(v));
    const Vec3 half = 0.5 * (world.upper.col(v) - world.lower.col(v));
    const double reach = std::abs(n.x()) * half.x() + std::abs(n.y()) * half.y() + std::abs(n.z()) * half.z();
    return std::make_pair(n.dot(centre) - reach, n.dot(centre) + reach);
  };
  double from_high = -INFINITY, to_low = INFINITY;
  for (const int v : from) from_high = std::max(from_high, projection(v).second);
  for (const int v : to) to_low = std::min(to_low, projection(v).first);
  return to_low - from_high > world.gap * (std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z()));
}

Vec3 centre(const QueryWorld& world, int v) { return 0.5 * (world.lower.col(v) + world.upper.col(v)); }

struct Reference {
  std::set<std::pair<int, int>> vertex_face, edge_edge;
};

// Every vertex-face and edge-edge pair of mesh 0 against itself and against the other meshes
// whose boxes are within the gap (`directional`: and not apart along the direction between the
// closest points of the box centres).
Reference brute_force(const QueryWorld& world, bool directional) {
  Reference reference;
  const auto vertex_face = [&](const QueryMesh& vm, int v, const QueryMesh& fm, int t) {
    const int p = vm.offsets.vertex + v;
    const int a = fm.offsets.vertex + fm.triangles(0, t), b = fm.offsets.vertex + fm.triangles(1, t),
              c = fm.offsets.vertex + fm.triangles(2, t);
    if (p == a || p == b || p == c) return;
    bool used = false;  // a vertex no triangle uses is never a candidate
    for (int s = 0; s < vm.triangles.cols(); ++s) used = used || (vm.triangles.col(s).array() == v).any();
    if (!used) return;
    if (!boxes_within_gap(box_over(world, {p}), box_over(world, {a, b, c}), world.gap)) return;
    if (directional) {
      const PointTriangleClosest closest =
          point_triangle_closest(centre(world, p), centre(world, a), centre(world, b), centre(world, c));
      if (closest.distance > 0.0 &&
          apart_along(world, {a, b, c}, {p}, (centre(world, p) - closest.closest) / closest.distance)) {
        return;
      }
    }
    reference.vertex_face.insert({p, fm.offsets.triangle + t});
  };
  const auto edge_edge = [&](const QueryMesh& em, int e, const QueryMesh& fm, int f) {
    const int a0 = em.offsets.vertex + em.topology.edges(0, e),
              a1 = em.offsets.vertex + em.topology.edges(1, e);
    const int b0 = fm.offsets.vertex + fm.topology.edges(0, f),
              b1 = fm.offsets.vertex + fm.topology.edges(1, f);
    if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) return;
    if (!boxes_within_gap(box_over(world, {a0, a1}), box_over(world, {b0, b1}), world.gap)) return;
    if (directional) {
      const Vec3 offset =
          edge_edge_offset(centre(world, a0), centre(world, a1), centre(world, b0), centre(world, b1));
      const double length = offset.norm();
      if (length > 0.0 && apart_along(world, {a0, a1}, {b0, b1}, offset / length)) return;
    }
    const int g = em.offsets.edge + e, h = fm.offsets.edge + f;
    reference.edge_edge.insert({std::min(g, h), std::max(g, h)});
  };
  const QueryMesh& own = world.meshes[0];
  for (size_t m = 0; m < world.meshes.size(); ++m) {
    const QueryMesh& other = world.meshes[m];
    for (int v = 0; v < own.num_vertices; ++v) {
      for (int t = 0; t < other.triangles.cols(); ++t) vertex_face(own, v, other, t);
    }
    if (m > 0) {
      for (int v = 0; v < other.num_vertices; ++v) {
        for (int t = 0; t < own.triangles.cols(); ++t) vertex_face(other, v, own, t);
      }
    }
    for (int e = 0; e < own.topology.num_edges(); ++e) {
      for (int f = (m == 0 ? e + 1 : 0); f < other.topology.num_edges(); ++f) edge_edge(own, e, other, f);
    }
  }
  return reference;
}

std::vector<std::pair<int, int>> listed(const std::vector<VertexFacePair>& pairs) {
  std::vector<std::pair<int, int>> out;
  for (const VertexFacePair& p : pairs) out.push_back({p.vertex, p.triangle});
  return out;
}
std::vector<std::pair<int, int>> listed(const std::vector<EdgeEdgePair>& pairs) {
  std::vector<std::pair<int, int>> out;
  for (const EdgeEdgePair& p : pairs) out.push_back({p.edge_a, p.edge_b});
  return out;
}
std::vector<std::pair<int, int>> listed(const std::set<std::pair<int, int>>& pairs) {
  return {pairs.begin(), pairs.end()};
}

template <typename T>
bool sorted_and_unique(const std::vector<T>& items) {
  return std::adjacent_find(items.begin(), items.end(), [](const T& x, const T& y) { return !(x < y); }) ==
         items.end();
}

bool includes(const std::set<std::pair<int, int>>& all, const std::set<std::pair<int, int>>& part) {
  return std::includes(all.begin(), all.end(), part.begin(), part.end());
}

// ---- Tests -----------------------------------------------------------------------------------

TEST(PrimitiveQueries, RandomMeshesMatchTheBruteForceReference) {
  for (const unsigned seed : {1u, 2u, 3u, 4u}) {
    for (const bool between : {false, true}) {
      QueryWorld world;
      add_swept_grid(world, 14, seed, Vec3::Zero(),
                     seed % 2 ? GridTriangulation::alternating : GridTriangulation::regular);
      if (between) add_swept_grid(world, 9, seed + 100, Vec3(0.2, 0.3, 0.05), GridTriangulation::cross);
      world.build();
      const CollisionCandidates candidates = world.query();
      const Reference axes = brute_force(world, false);
      const Reference directional = brute_force(world, true);
      EXPECT_TRUE(sorted_and_unique(candidates.vertex_face));
      EXPECT_TRUE(sorted_and_unique(candidates.edge_edge));
      EXPECT_EQ(listed(candidates.vertex_face), listed(directional.vertex_face)) << seed << " " << between;
      EXPECT_EQ(listed(candidates.edge_edge), listed(directional.edge_edge)) << seed << " " << between;
      // The box filter alone keeps more; the directional test only ever drops.
      EXPECT_TRUE(includes(axes.vertex_face, directional.vertex_face));
      EXPECT_TRUE(includes(axes.edge_edge, directional.edge_edge));
      EXPECT_GT(axes.vertex_face.size() + axes.edge_edge.size(),
                directional.vertex_face.size() + directional.edge_edge.size());
      EXPECT_GT(directional.vertex_face.size(), 100u) << seed << " " << between;
      EXPECT_GT(directional.edge_edge.size(), 100u) << seed << " " << between;
      if (between) {  // pairs between the meshes are there, in combined indices
        const int first_of_second = world.meshes[1].offsets.edge;
        EXPECT_TRUE(std::any_of(candidates.edge_edge.begin(), candidates.edge_edge.end(),
                                [&](const EdgeEdgePair& p) { return p.edge_b >= first_of_second; }));
      }
    }
  }
}

TEST(PrimitiveQueries, TheSameListsOnAnyThreadCount) {
  QueryWorld world;
  add_swept_grid(world, 40, 7, Vec3::Zero(), GridTriangulation::alternating);
  add_swept_grid(world, 20, 8, Vec3(0.1, 0.2, 0.02), GridTriangulation::regular);
  world.gap = 0.03;
  world.build();
  const int threads_before = omp_get_max_threads();
  std::vector<CollisionCandidates> results;
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    results.push_back(world.query());
  }
  omp_set_num_threads(threads_before);
  ASSERT_GT(results[0].edge_edge.size(), 1000u);
  for (int k = 1; k < 3; ++k) {
    EXPECT_TRUE(results[k].vertex_face == results[0].vertex_face) << k + 1 << " threads";
    EXPECT_TRUE(results[k].edge_edge == results[0].edge_edge) << k + 1 << " threads";
  }
}

// Mesh 0's walk of its triangle hierarchy with `culled` flags (and, with `within`, only inside
// those nodes).
CollisionCandidates culled_walk(const QueryWorld& world, const std::vector<char>& culled,
                                const std::vector<int>* within = nullptr) {
  const QueryMesh& mesh = world.meshes[0];
  const OwnedPrimitives owned = owned_primitives(mesh.topology, static_cast<int>(mesh.triangles.cols()));
  BvhQueryBuffers buffers;
  CollisionCandidates candidates;
  append_self_candidates_culled(mesh.view(), owned, world.boxes(), culled, within, buffers, candidates);
  sort_candidates(candidates);
  return candidates;
}

TEST(PrimitiveQueries, OwnedPrimitivesGiveEachVertexAndEdgeOneTriangleThatHoldsIt) {
  const TriangleMesh grid = make_grid(5, 4, 1.0, 1.0, GridTriangulation::alternating);
  const Triangles& triangles = grid.triangles;
  const int unused = grid.num_vertices();  // a vertex no triangle uses has no owner
  const MeshTopology topology = build_topology(triangles, unused + 1);
  const OwnedPrimitives owned = owned_primitives(topology, static_cast<int>(triangles.cols()));
  std::vector<int> vertex_owners(unused + 1, 0), edge_owners(topology.num_edges(), 0);
  for (int t = 0; t < triangles.cols(); ++t) {
    for (int k = owned.vertex_start[t]; k < owned.vertex_start[t + 1]; ++k) {
      const int v = owned.vertices[k];
      ++vertex_owners[v];
      EXPECT_TRUE(triangles(0, t) == v || triangles(1, t) == v || triangles(2, t) == v);
    }
    for (int k = owned.edge_start[t]; k < owned.edge_start[t + 1]; ++k) {
      const int e = owned.edges[k];
      ++edge_owners[e];
      EXPECT_TRUE(topology.edge_triangles(0, e) == t || topology.edge_triangles(1, e) == t);
    }
  }
  for (int v = 0; v < unused; ++v) EXPECT_EQ(vertex_owners[v], 1) << "vertex " << v;
  EXPECT_EQ(vertex_owners[unused], 0);
  for (int e = 0; e < topology.num_edges(); ++e) EXPECT_EQ(edge_owners[e], 1) << "edge " << e;
}

// The walk over triangle pairs writes the full query's pairs exactly, less those whose owners lie
// in one culled region; walking only inside the culled regions writes exactly those.
TEST(PrimitiveQueries, TheCulledWalkSkipsExactlyThePairsWithinCulledNodes) {
  for (const unsigned seed : {5u, 6u, 7u}) {
    QueryWorld world;
    add_swept_grid(world, 16, seed, Vec3::Zero(), GridTriangulation::alternating);
    world.gap = 0.05;
    world.build();
    const QueryMesh& mesh = world.meshes[0];
    const Bvh& bvh = mesh.triangle_bvh;
    const CollisionCandidates full = world.query();  // one mesh: its self pairs
    ASSERT_GT(full.vertex_face.size() + full.edge_edge.size(), 100u);
    const CollisionCandidates unculled = culled_walk(world, std::vector<char>(bvh.nodes().size(), 0));
    EXPECT_TRUE(unculled.vertex_face == full.vertex_face) << seed;
    EXPECT_TRUE(unculled.edge_edge == full.edge_edge) << seed;

    // Random flags, a few near the root too: the walk must hold for any set of culled nodes.
    std::mt19937 rng(seed);
    std::vector<char> culled(bvh.nodes().size(), 0);
    for (size_t n = 1; n < culled.size(); ++n) culled[n] = std::uniform_int_distribution<int>(0, 9)(rng) == 0;
    std::vector<int> region;
    culled_regions(bvh, culled, region);
    const OwnedPrimitives owned = owned_primitives(mesh.topology, static_cast<int>(mesh.triangles.cols()));
    std::vector<int> vertex_owner(mesh.num_vertices, -1), edge_owner(mesh.topology.num_edges(), -1);
    for (int t = 0; t < mesh.triangles.cols(); ++t) {
      for (int k = owned.vertex_start[t]; k < owned.vertex_start[t + 1]; ++k)
        vertex_owner[owned.vertices[k]] = t;
      for (int k = owned.edge_start[t]; k < owned.edge_start[t + 1]; ++k) edge_owner[owned.edges[k]] = t;
    }
    const auto same_region = [&](int s, int t) { return region[s] >= 0 && region[s] == region[t]; };
    CollisionCandidates kept, skipped;
    for (const VertexFacePair& pair : full.vertex_face) {
      (same_region(vertex_owner[pair.vertex], pair.triangle) ? skipped : kept).vertex_face.push_back(pair);
    }
    for (const EdgeEdgePair& pair : full.edge_edge) {
      (same_region(edge_owner[pair.edge_a], edge_owner[pair.edge_b]) ? skipped : kept)
          .edge_edge.push_back(pair);
    }
    ASSERT_GT(skipped.vertex_face.size() + skipped.edge_edge.size(), 10u) << "culling dropped some pairs";
    const CollisionCandidates walked = culled_walk(world, culled);
    EXPECT_TRUE(walked.vertex_face == kept.vertex_face) << seed;
    EXPECT_TRUE(walked.edge_edge == kept.edge_edge) << seed;

    // The regions' roots: the topmost culled nodes.
    std::vector<int> roots;
    for (int n = 0; n < static_cast<int>(culled.size());) {
      if (culled[n]) {
        roots.push_back(n);
        n = bvh.nodes()[n].next;
      } else {
        ++n;
      }
    }
    const CollisionCandidates inside = culled_walk(world, std::vector<char>(culled.size(), 0), &roots);
    EXPECT_TRUE(inside.vertex_face == skipped.vertex_face) << seed;
    EXPECT_TRUE(inside.edge_edge == skipped.edge_edge) << seed;
  }
}

TEST(PrimitiveQueries, ReQueryOfMovedVerticesGivesEveryCandidateWithAMovedVertex) {
  QueryWorld world;
  add_swept_grid(world, 20, 9, Vec3::Zero(), GridTriangulation::alternating);
  add_swept_grid(world, 12, 10, Vec3(0.2, 0.3, 0.05), GridTriangulation::regular);
  world.build();
  // Some vertices of mesh 0 move farther: their boxes grow, the hierarchies are refitted.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> push(-0.05, 0.05);
  std::vector<char> moved(world.lower.cols(), 0);
  for (int v = 0; v < world.meshes[0].num_vertices; v += 5) {
    moved[v] = 1;
    const Vec3 x = world.upper.col(v) + random_vec3(push, rng);
    world.lower.col(v) = world.lower.col(v).cwiseMin(x);
    world.upper.col(v) = world.upper.col(v).cwiseMax(x);
  }
  world.meshes[0].refit(world.lower, world.upper, world.gap);

  MovedPrimitives primitives;
  list_moved_primitives(world.meshes[0].view(), moved, primitives);
  std::vector<std::vector<int>> scratch;
  CollisionCandidates requery;
  append_moved_primitive_candidates(world.meshes[0].view(), primitives, world.meshes[0].view(), true,
                                    world.boxes(), scratch, requery);
  append_moved_primitive_candidates(world.meshes[0].view(), primitives, world.meshes[1].view(), false,
                                    world.boxes(), scratch, requery);
  sort_candidates(requery);

  // The reference: every pair of the brute force at the grown boxes with a moved vertex.
  const Reference all = brute_force(world, true);
  const QueryMesh& own = world.meshes[0];
  const auto is_moved = [&](int v) { return moved[v] != 0; };
  const auto edge_moved = [&](int e) {
    if (e >= world.meshes[1].offsets.edge) return false;
    return is_moved(own.topology.edges(0, e)) || is_moved(own.topology.edges(1, e));
  };
  Reference expected;
  for (const auto& [v, t] : all.vertex_face) {
    const bool face_moved =
        t < world.meshes[1].offsets.triangle &&
        (is_moved(own.triangles(0, t)) || is_moved(own.triangles(1, t)) || is_moved(own.triangles(2, t)));
    if (is_moved(v) || face_moved) expected.vertex_face.insert({v, t});
  }
  for (const auto& [e, f] : all.edge_edge) {
    if (edge_moved(e) || edge_moved(f)) expected.edge_edge.insert({e, f});
  }
  EXPECT_GT(expected.vertex_face.size(), 100u);
  EXPECT_GT(expected.edge_edge.size(), 100u);
  EXPECT_EQ(listed(requery.vertex_face), listed(expected.vertex_face));
  EXPECT_EQ(listed(requery.edge_edge), listed(expected.edge_edge));
}

TEST(PrimitiveQueries, AHingeFoldedFlatIsACandidate) {
  // Triangles (0, 1, 2) and (1, 0, 3) share the edge 0-1; vertex 3 is folded over onto the first
  // triangle, 1e-3 above it: only primitives of neighbouring triangles meet.
  QueryWorld world;
  world.gap = 0.01;
  world.lower.resize(3, 4);
  world.lower << 0.0, 1.0, 0.3, 0.3,  //
      0.0, 0.0, 1.0, 0.5,             //
      0.0, 0.0, 0.0, 1e-3;
  world.upper = world.lower;
  Triangles triangles(3, 2);
  triangles << 0, 1, 1, 0, 2, 3;
  world.add(triangles, 4);
  world.build();
  const CollisionCandidates candidates = world.query();
  EXPECT_TRUE(
      std::binary_search(candidates.vertex_face.begin(), candidates.vertex_face.end(), VertexFacePair{3, 0}));
  EXPECT_EQ(listed(candidates.vertex_face), listed(brute_force(world, true).vertex_face));
  EXPECT_EQ(listed(candidates.edge_edge), listed(brute_force(world, true).edge_edge));
}

TEST(PrimitiveQueries, AFlatGridAtRestHasNoCandidates) {
  // Every pair of a flat grid that shares no vertex is at least half a cell's diagonal apart, far
  // more than the gap; yet a right triangle's box holds the corner it lacks and a diagonal's box
  // the sides of the next cells, so the coordinate-box filter alone keeps thousands of them.
  const TriangleMesh mesh = make_grid(32, 32, 1.0, 1.0, GridTriangulation::alternating);
  QueryWorld world;
  world.gap = 0.005;  // cells of 1/31 m
  world.lower = mesh.positions;
  world.upper = mesh.positions;
  world.add(mesh.triangles, mesh.num_vertices());
  world.build();
  const CollisionCandidates candidates = world.query();
  EXPECT_TRUE(candidates.vertex_face.empty()) << candidates.vertex_face.size();
  EXPECT_TRUE(candidates.edge_edge.empty()) << candidates.edge_edge.size();
  const Reference axes = brute_force(world, false);
  EXPECT_GT(axes.vertex_face.size() + axes.edge_edge.size(), 1000u);
}

TEST(PrimitiveQueries, ANonManifoldFinAndAnUnusedVertex) {
  // Three triangles on edge (p, q) and F = (a, b, z); vertex u belongs to no triangle and is never
  // a candidate, however close it lies.
  enum { p, q, a, b, c, z, u };
  QueryWorld world;
  world.gap = 1.0;
  world.lower.resize(3, 7);
  world.lower << 0.0, 1.0, 0.5, 0.5, 0.5, 0.5, 0.5,  //
      0.0, 0.0, 0.5, -0.5, 0.0, 0.0, 0.0,            //
      0.0, 0.0, 0.0, 0.0, 0.5, 0.01, 0.02;
  world.upper = world.lower;
  Triangles triangles(3, 4);
  triangles << p, q, p, a,  //
      q, p, q, b,           //
      a, b, c, z;
  world.add(triangles, 7);
  ASSERT_EQ(world.meshes[0].topology.non_manifold_edges.size(), 1u);
  world.build();
  const CollisionCandidates candidates = world.query();
  const Reference reference = brute_force(world, true);
  EXPECT_EQ(listed(candidates.vertex_face), listed(reference.vertex_face));
  EXPECT_EQ(listed(candidates.edge_edge), listed(reference.edge_edge));
  EXPECT_FALSE(candidates.edge_edge.empty());
  for (const VertexFacePair& pair : candidates.vertex_face) EXPECT_NE(pair.vertex, u);
}

// Positions drawn inside each vertex's box grown by `slack` per coordinate (corners half the time).
Positions positions_in_boxes(const Positions& lower, const Positions& upper, double slack,
                             std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Positions x(3, lower.cols());
  for (Eigen::Index v = 0; v < lower.cols(); ++v) {
    for (int d = 0; d < 3; ++d) {
      const double w = unit(rng) < 0.5 ? unit(rng) : std::round(unit(rng));
      x(d, v) = lower(d, v) - slack + w * (upper(d, v) - lower(d, v) + 2.0 * slack);
    }
  }
  return x;
}

// What CollisionPhase::verify_motion relies on: with every vertex within `slack` (per
// coordinate) of its box, a primitive pair closer than gap - 2 slack is a candidate. Checked by
// distances on positions drawn in the grown boxes, over every vertex-face pair whose vertex is
// not a corner of the face and every edge-edge pair without a common vertex, within mesh 0
// (neighbours included) and between it and mesh 1. Returns the number of close pairs seen.
int expect_every_close_pair_is_a_candidate(const QueryWorld& world, unsigned seed) {
  const CollisionCandidates candidates = world.query();
  const QueryMesh& a = world.meshes[0];
  const QueryMesh& b = world.meshes[1];
  const int na = a.num_vertices;
  Triangles triangles(3, a.triangles.cols() + b.triangles.cols());
  triangles << a.triangles, b.triangles.array() + na;
  Eigen::Matrix2Xi edges(2, a.topology.num_edges() + b.topology.num_edges());
  edges << a.topology.edges, b.topology.edges.array() + na;
  const auto mesh_of = [&](int v) { return v < na ? 0 : 1; };
  std::mt19937 rng(seed);
  int close_pairs = 0;
  for (const double slack : {0.0, 0.3 * world.gap}) {
    const double within = world.gap - 2.0 * slack;
    for (int draw = 0; draw < 3; ++draw) {
      const Positions x = positions_in_boxes(world.lower, world.upper, slack, rng);
      for (int v = 0; v < x.cols(); ++v) {
        for (int t = 0; t < triangles.cols(); ++t) {
          const Vec3i c = triangles.col(t);
          if (mesh_of(v) == 1 && mesh_of(c[0]) == 1) continue;  // mesh 1 is not queried against itself
          if (c[0] == v || c[1] == v || c[2] == v) continue;
          if (point_triangle_closest(x.col(v), x.col(c[0]), x.col(c[1]), x.col(c[2])).distance >= within)
            continue;
          ++close_pairs;
          EXPECT_TRUE(std::binary_search(candidates.vertex_face.begin(), candidates.vertex_face.end(),
                                         VertexFacePair{v, t}))
              << v << " " << t << " slack " << slack;
        }
      }
      for (int e = 0; e < edges.cols(); ++e) {
        for (int f = e + 1; f < edges.cols(); ++f) {
          const Eigen::Vector2i p = edges.col(e), q = edges.col(f);
          if (mesh_of(p[0]) == 1 && mesh_of(q[0]) == 1) continue;
          if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1]) continue;
          if (edge_edge_closest(x.col(p[0]), x.col(p[1]), x.col(q[0]), x.col(q[1])).distance >= within)
            continue;
          ++close_pairs;
          EXPECT_TRUE(std::binary_search(candidates.edge_edge.begin(), candidates.edge_edge.end(),
                                         EdgeEdgePair{e, f}))
              << e << " " << f << " slack " << slack;
        }
      }
    }
  }
  return close_pairs;
}

TEST(PrimitiveQueries, EveryPairThatComesWithinTheGapInsideItsBoxesIsACandidate) {
  QueryWorld world;
  add_swept_grid(world, 24, 3, Vec3::Zero(), GridTriangulation::alternating);
  add_swept_grid(world, 16, 4, Vec3(0.2, 0.3, 0.05), GridTriangulation::alternating);
  world.build();
  EXPECT_GT(expect_every_close_pair_is_a_candidate(world, 11), 1000);
}

TEST(PrimitiveQueries, EveryCloseNeighbourPairOfATightRollWithAFoldedHemIsACandidate) {
  // A grid rolled tightly around the y axis (turns a few gaps apart) whose last rows fold back
  // over the roll as a hem, moving a little over the step: pairs between neighbours one or two
  // rows apart come within the gap.
  QueryWorld world;
  const double gap = world.gap;
  const TriangleMesh grid = make_grid(60, 6, 1.0, 0.2, GridTriangulation::alternating);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> noise(-0.1 * gap, 0.1 * gap);
  Positions x_start = grid.positions;
  const double pitch = 1.5 * gap;  // radial distance between turns
  for (int v = 0; v < grid.num_vertices(); ++v) {
    const double s = grid.positions(0, v) + 0.5;  // arc length along the roll, 0 .. 1
    const double y = grid.positions(1, v);
    if (s < 0.8) {  // Archimedean spiral r = r0 + pitch theta / 2pi, arc length ~ r dtheta
      const double r0 = 0.02;
      double theta = 0.0;
      for (int k = 0; k < 200; ++k) theta += (s / 200.0) / (r0 + pitch * theta / (2.0 * M_PI));
      const double r = r0 + pitch * theta / (2.0 * M_PI);
      x_start.col(v) = Vec3(r * std::cos(theta), y, r * std::sin(theta));
    } else {  // the hem: folded back flat along the first row's tangent, half a gap above it
      x_start.col(v) = Vec3(0.02 + (s - 0.8) * 0.9, y, 0.5 * gap + 0.3 * (s - 0.8) * gap);
    }
    x_start.col(v) += random_vec3(noise, rng);
  }
  Positions x_end = x_start;
  for (int v = 0; v < grid.num_vertices(); ++v) x_end.col(v) += random_vec3(noise, rng);
  add_swept(world, grid.triangles, x_start, x_end);
  add_swept_grid(world, 8, 22, Vec3(0.0, 0.0, 0.3), GridTriangulation::alternating);
  world.build();

  // Neighbour pairs (every triangle around the vertex shares a corner with the face) within the
  // gap exist, and are candidates.
  const CollisionCandidates candidates = world.query();
  const QueryMesh& own = world.meshes[0];
  int neighbour_pairs = 0;
  for (const VertexFacePair& pair : candidates.vertex_face) {
    if (pair.vertex >= world.meshes[1].offsets.vertex || pair.triangle >= world.meshes[1].offsets.triangle)
      continue;
    bool only_neighbours = true;
    for (int k = own.topology.vertex_triangle_start[pair.vertex];
         k < own.topology.vertex_triangle_start[pair.vertex + 1]; ++k) {
      only_neighbours =
          only_neighbours && share_vertex(own.triangles, own.topology.vertex_triangles[k], pair.triangle);
    }
    neighbour_pairs += only_neighbours;
  }
  EXPECT_GT(neighbour_pairs, 10);
  EXPECT_GT(expect_every_close_pair_is_a_candidate(world, 23), 1000);
}

}  // namespace
}  // namespace weft
