#pragma once
// A triangle mesh: positions, triangles and optional per-vertex texture coordinates.
#include "core/math.hpp"

namespace weft {

struct TriangleMesh {
  Positions positions;    // vertex positions (3 x n_vertices)
  Triangles triangles;    // vertex indices, counter-clockwise seen from the front (3 x n_triangles)
  Eigen::Matrix2Xd uvs;   // texture coordinates (2 x n_vertices), or empty (2 x 0)

  int num_vertices() const { return static_cast<int>(positions.cols()); }
  int num_triangles() const { return static_cast<int>(triangles.cols()); }
  bool has_uvs() const { return uvs.cols() == positions.cols() && uvs.cols() > 0; }
};

// Area-weighted unit vertex normals of `triangles` at `positions` (3 x n_vertices); a vertex
// touching no triangle of non-zero area gets (0, 0, 0).
Positions vertex_normals(const Positions& positions, const Triangles& triangles);

// Total area of the mesh's triangles.
double surface_area(const Positions& positions, const Triangles& triangles);

// Applies x -> R * (scale * x) + translation to every position.
void transform_positions(Positions& positions, const Mat3& rotation, double scale, const Vec3& translation);

}  // namespace weft
