#pragma once
// Procedural meshes: cloth grids and closed solids (for colliders and soft bodies).
#include "core/triangle_mesh.hpp"

namespace weft {

// How each grid quad is cut into triangles.
enum class GridTriangulation {
  regular,      // every quad cut along the same diagonal
  alternating,  // diagonals alternate in a checkerboard (no preferred shear direction)
  cross,        // a vertex added at each quad's centre, four triangles per quad
};

// A grid of nx by ny lattice vertices in the local XY plane, centred at the origin, front face
// towards +Z. Lattice vertex (i, j) is index j * nx + i at x = -width/2 + i * width/(nx-1),
// y = -height/2 + j * height/(ny-1), uv = (i/(nx-1), j/(ny-1)). With `cross`, the centre of
// quad (i, j) follows the lattice at index nx*ny + j*(nx-1) + i. Requires nx, ny >= 2.
TriangleMesh make_grid(int nx, int ny, double width, double height, GridTriangulation triangulation);

// Closed UV sphere centred at the origin with a single vertex at each pole (+-Y), outward
// facing; `slices` around the Y axis (>= 3), `stacks` from pole to pole (>= 2).
TriangleMesh make_uv_sphere(double radius, int slices, int stacks);

// Closed axis-aligned box centred at the origin, outward facing, 8 shared corner vertices.
TriangleMesh make_box(const Vec3& half_extents);

// Cylinder around the Y axis centred at the origin, outward facing, `segments` around (>= 3).
// With `capped` it is closed (a centre vertex on each cap), otherwise an open tube.
TriangleMesh make_cylinder(double radius, double height, int segments, bool capped);

}  // namespace weft
