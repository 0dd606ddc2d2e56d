#include "check/tangle_check.hpp"

#include <cstdio>
#include <map>
#include <utility>

namespace weft {

namespace {

const NamedSurface& surface(const TangleInput& input, int index) {
  const int num_cloths = static_cast<int>(input.cloths.size());
  return index < num_cloths ? input.cloths[index] : input.colliders[index - num_cloths];
}

Vec3 corner_mean(const NamedSurface& s, int triangle) {
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 3; ++k) sum += s.positions->col((*s.triangles)(k, triangle));
  return sum / 3.0;
}

// Triangle pairs among cloths and between cloths and colliders, grouped by surface pair.
void count_intersections(const TangleInput& input, TangleReport& report) {
  std::vector<CheckedMesh> meshes;
  for (const NamedSurface& cloth : input.cloths) meshes.push_back({cloth.positions, cloth.triangles, false});
  for (const NamedSurface& collider : input.colliders) {
    meshes.push_back({collider.positions, collider.triangles, true});
  }
  std::map<std::pair<int, int>, SurfacePairTangle> groups;
  for (const TriangleIntersection& hit : find_triangle_intersections(meshes)) {
    SurfacePairTangle& group = groups[{hit.mesh_a, hit.mesh_b}];
    if (group.pairs++ == 0) {
      group.surface_a = hit.mesh_a;
      group.surface_b = hit.mesh_b;
      group.first_triangle_a = hit.triangle_a;
      group.first_triangle_b = hit.triangle_b;
      group.near = 0.5 * (corner_mean(surface(input, hit.mesh_a), hit.triangle_a) +
                          corner_mean(surface(input, hit.mesh_b), hit.triangle_b));
    }
    ++report.intersecting_pairs;
    report.pairs.push_back(hit);
  }
  for (auto& [key, group] : groups) report.surface_pairs.push_back(group);
}

bool is_held(const TangleInput& input, int cloth, int solid) {
  return cloth < static_cast<int>(input.held.size()) && solid < static_cast<int>(input.held[cloth].size()) &&
         input.held[cloth][solid] != 0;
}

// Cloth vertices strictly inside each solid that does not hold the cloth.
void count_vertices_inside(const TangleInput& input, TangleReport& report) {
  for (int c = 0; c < static_cast<int>(input.cloths.size()); ++c) {
    const Positions& x = *input.cloths[c].positions;
    for (int s = 0; s < static_cast<int>(input.solids.size()); ++s) {
      if (is_held(input, c, s)) continue;
      VerticesInsideSolid found;
      found.cloth = c;
      found.collider = input.solid_collider[s];
      for (int i = 0; i < static_cast<int>(x.cols()); ++i) {
        const double distance = reference_signed_distance(input.solids[s], x.col(i));
        if (!(distance < 0.0)) continue;
        if (found.vertices++ == 0 || -distance > found.deepest) {
          found.deepest_vertex = i;
          found.deepest = -distance;
        }
      }
      if (found.vertices == 0) continue;
      report.vertices_inside_colliders += found.vertices;
      report.inside.push_back(found);
    }
  }
}

}  // namespace

std::vector<std::vector<char>> solids_holding_cloths(const TangleInput& input) {
  std::vector<std::vector<char>> held(input.cloths.size(), std::vector<char>(input.solids.size(), 0));
  for (size_t c = 0; c < input.cloths.size(); ++c) {
    const Positions& x = *input.cloths[c].positions;
    for (size_t s = 0; s < input.solids.size(); ++s) {
      Eigen::Index inside = 0;
      for (Eigen::Index i = 0; i < x.cols(); ++i) inside += reference_signed_distance(input.solids[s], x.col(i)) < 0.0;
      held[c][s] = 2 * inside > x.cols();
    }
  }
  return held;
}

TangleReport check_tangles(const TangleInput& input) {
  TangleReport report;
  count_intersections(input, report);
  count_vertices_inside(input, report);
  return report;
}

std::string describe_tangles(const TangleReport& report, const TangleInput& input) {
  const int num_cloths = static_cast<int>(input.cloths.size());
  const auto kind = [&](int index) { return index < num_cloths ? "cloth" : "collider"; };
  std::vector<std::string> parts;
  char part[512];
  const auto add = [&](const std::string& piece) { parts.push_back(piece); };
  for (const SurfacePairTangle& g : report.surface_pairs) {
    const std::string& a = surface(input, g.surface_a).name;
    const std::string& b = surface(input, g.surface_b).name;
    const std::string who = g.surface_a == g.surface_b
                                ? std::string(kind(g.surface_a)) + " \"" + a + "\" through itself"
                            : g.surface_b < num_cloths ? "cloths \"" + a + "\" and \"" + b + "\""
                                                       : "cloth \"" + a + "\" and collider \"" + b + "\"";
    std::snprintf(part, sizeof part,
                  "%s: %d intersecting triangle pair%s (first: triangles %d and %d near (%.2f, %.2f, %.2f))",
                  who.c_str(), g.pairs, g.pairs == 1 ? "" : "s", g.first_triangle_a, g.first_triangle_b,
                  g.near.x(), g.near.y(), g.near.z());
    add(part);
  }
  for (const VerticesInsideSolid& v : report.inside) {
    std::snprintf(part, sizeof part,
                  "cloth \"%s\": %d vert%s inside collider \"%s\" (deepest: vertex %d, %.2g cm)",
                  input.cloths[v.cloth].name.c_str(), v.vertices, v.vertices == 1 ? "ex" : "ices",
                  input.colliders[v.collider].name.c_str(), v.deepest_vertex, 100.0 * v.deepest);
    add(part);
  }
  // The first few groups, so that a badly tangled scene still reads in one line.
  constexpr size_t shown = 4;
  std::string text;
  for (size_t i = 0; i < parts.size() && i < shown; ++i) text += (i == 0 ? "" : "; ") + parts[i];
  if (parts.size() > shown) text += "; and " + std::to_string(parts.size() - shown) + " more";
  return text;
}

}  // namespace weft
