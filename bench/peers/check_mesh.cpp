// Measures one simulator's final cloth mesh for the peer benchmark (bench/peers/run): the same
// figures for Weft, Bullet and Blender, whose meshes all arrive as Y-up OBJ files.
//   weft_check_mesh final.obj
// Prints one line of key=value fields:
//   vertices triangles min_y max_y inside_any inside_1cm max_depth intersecting_pairs
// "inside" counts vertices inside the scene's sphere (centre 0, radius 0.5); intersecting_pairs
// counts pairs of triangles that share no vertex and still intersect (Weft's exact check).
// Exit code 0: measured (whatever the figures are); 2: bad input, the message names the file.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "check/intersection_check.hpp"
#include "check/solid_distance.hpp"
#include "io/obj_io.hpp"

namespace {

// The drape scene's sphere (scenes/drape_sphere.json, bench/peers/README.md): centre 0, radius 0.5.
weft::AnalyticSolid drape_sphere() {
  weft::AnalyticSolid sphere;
  sphere.kind = weft::SolidKind::sphere;
  sphere.radius = 0.5;
  return sphere;
}
// Depth past which a vertex counts as through the sphere: bench/peers/README.md's 1 cm.
constexpr double deep_inside = 0.01;

struct MeshFigures {
  int vertices = 0;
  int triangles = 0;
  double min_y = 0.0;
  double max_y = 0.0;
  int inside_any = 0;      // vertices with depth > 0
  int inside_1cm = 0;      // vertices with depth > deep_inside
  double max_depth = 0.0;  // deepest vertex, 0 when none is inside
  int intersecting_pairs = 0;
};

MeshFigures measure(const weft::TriangleMesh& mesh) {
  MeshFigures figures;
  figures.vertices = mesh.num_vertices();
  figures.triangles = mesh.num_triangles();
  figures.min_y = mesh.positions.row(1).minCoeff();
  figures.max_y = mesh.positions.row(1).maxCoeff();
  const weft::AnalyticSolid sphere = drape_sphere();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double depth = -weft::reference_signed_distance(sphere, mesh.positions.col(v));
    if (depth <= 0.0) continue;
    ++figures.inside_any;
    if (depth > deep_inside) ++figures.inside_1cm;
    figures.max_depth = std::max(figures.max_depth, depth);
  }
  figures.intersecting_pairs =
      static_cast<int>(weft::find_triangle_intersections(mesh.positions, mesh.triangles).size());
  return figures;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s final.obj\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  try {
    const weft::TriangleMesh mesh = weft::read_obj(path);
    const MeshFigures f = measure(mesh);
    std::printf(
        "vertices=%d triangles=%d min_y=%.6f max_y=%.6f inside_any=%d inside_1cm=%d max_depth=%.6f "
        "intersecting_pairs=%d\n",
        f.vertices, f.triangles, f.min_y, f.max_y, f.inside_any, f.inside_1cm, f.max_depth,
        f.intersecting_pairs);
  } catch (const std::exception& error) {
    // read_obj's IoError already names the file; the checker's invalid_argument does not.
    const std::string message = error.what();
    const bool names_file = message.compare(0, path.size(), path) == 0;
    std::fprintf(stderr, "weft_check_mesh: %s%s\n", names_file ? "" : (path + ": ").c_str(), message.c_str());
    return 2;
  }
  return 0;
}
