#pragma once
// Loop subdivision of a displayed triangle mesh (Loop 1987, with Warren's interior weights), so a
// coarse simulation mesh renders smooth. The topology is subdivided once; every frame the fine
// positions are one sparse product with the coarse ones. No OpenGL.
#include <Eigen/SparseCore>

#include "core/math.hpp"

namespace weft {

struct LoopSubdivision {
  int levels = 0;
  Triangles triangles;                         // fine triangles, same orientation (3 x n_fine_triangles)
  Eigen::SparseMatrix<double> coarse_to_fine;  // fine vertex = weights of coarse vertices (n_fine x n_coarse)

  int num_fine_vertices() const { return static_cast<int>(coarse_to_fine.rows()); }
  // Fine positions (3 x n_fine) of coarse positions (3 x n_coarse); any per-vertex field works alike.
  Positions apply(const Positions& coarse) const { return coarse * coarse_to_fine.transpose(); }
  Eigen::VectorXd apply(const Eigen::VectorXd& coarse) const { return coarse_to_fine * coarse; }
};

// `levels` rounds of subdivision (0: the mesh itself). Fine vertex i < num_vertices is the
// smoothed coarse vertex i; each round adds one vertex per edge. Interior vertices and edges use
// Loop's masks; boundary (and non-manifold) edges use the cubic B-spline curve masks; a boundary
// vertex in a single triangle (a grid corner) stays where it is.
LoopSubdivision make_loop_subdivision(const Triangles& triangles, int num_vertices, int levels);

}  // namespace weft
