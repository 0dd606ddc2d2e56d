#include "core/mesh_generators.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace weft {

namespace {

void require_positive(double value, const char* function, const char* name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw std::invalid_argument(std::string(function) + ": " + name + " must be positive and finite, got " +
                                std::to_string(value));
  }
}

void require_at_least(int value, int minimum, const char* function, const char* name) {
  if (value < minimum) {
    throw std::invalid_argument(std::string(function) + ": " + name + " must be at least " +
                                std::to_string(minimum) + ", got " + std::to_string(value));
  }
}

// Refuses sizes whose triangle count would overflow int indices (3 per triangle, as in topology).
void require_int_indices(std::int64_t num_triangles, const char* function) {
  if (num_triangles > std::numeric_limits<int>::max() / 3) {
    throw std::invalid_argument(std::string(function) + ": mesh too large for int indices");
  }
}

// Point at azimuth `angle` on a circle of `radius` around the Y axis at height `y`; the angle
// runs from +Z towards +X.
Vec3 point_around_y(double radius, double angle, double y) {
  return Vec3(radius * std::sin(angle), y, radius * std::cos(angle));
}

}  // namespace

TriangleMesh make_grid(int nx, int ny, double width, double height, GridTriangulation triangulation) {
  require_at_least(nx, 2, "make_grid", "nx");
  require_at_least(ny, 2, "make_grid", "ny");
  require_positive(width, "make_grid", "width");
  require_positive(height, "make_grid", "height");
  require_int_indices(4 * static_cast<std::int64_t>(nx - 1) * (ny - 1), "make_grid");

  const bool cross = triangulation == GridTriangulation::cross;
  const int num_lattice = nx * ny;
  const int num_quads = (nx - 1) * (ny - 1);
  const int num_vertices = cross ? num_lattice + num_quads : num_lattice;
  const double dx = width / (nx - 1);
  const double dy = height / (ny - 1);

  // Lattice vertices, then (with cross) one vertex at each quad's centre.
  TriangleMesh mesh;
  mesh.positions.resize(3, num_vertices);
  mesh.uvs.resize(2, num_vertices);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      mesh.positions.col(j * nx + i) = Vec3(-0.5 * width + i * dx, -0.5 * height + j * dy, 0.0);
      mesh.uvs.col(j * nx + i) = Vec2(double(i) / (nx - 1), double(j) / (ny - 1));
    }
  }
  if (cross) {
    for (int j = 0; j < ny - 1; ++j) {
      for (int i = 0; i < nx - 1; ++i) {
        const int centre = num_lattice + j * (nx - 1) + i;
        mesh.positions.col(centre) = Vec3(-0.5 * width + (i + 0.5) * dx, -0.5 * height + (j + 0.5) * dy, 0.0);
        mesh.uvs.col(centre) = Vec2((i + 0.5) / (nx - 1), (j + 0.5) / (ny - 1));
      }
    }
  }

  // Quad (i, j) has corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1),
  // counter-clockwise seen from +Z.
  mesh.triangles.resize(3, (cross ? 4 : 2) * num_quads);
  int t = 0;
  for (int j = 0; j < ny - 1; ++j) {
    for (int i = 0; i < nx - 1; ++i) {
      const int a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      switch (triangulation) {
        case GridTriangulation::regular:
          mesh.triangles.col(t++) << a, b, c;
          mesh.triangles.col(t++) << a, c, d;
          break;
        case GridTriangulation::alternating:
          if ((i + j) % 2 == 0) {
            mesh.triangles.col(t++) << a, b, c;
            mesh.triangles.col(t++) << a, c, d;
          } else {
            mesh.triangles.col(t++) << a, b, d;
            mesh.triangles.col(t++) << b, c, d;
          }
          break;
        case GridTriangulation::cross: {
          const int centre = num_lattice + j * (nx - 1) + i;
          mesh.triangles.col(t++) << a, b, centre;
          mesh.triangles.col(t++) << b, c, centre;
          mesh.triangles.col(t++) << c, d, centre;
          mesh.triangles.col(t++) << d, a, centre;
          break;
        }
      }
    }
  }
  return mesh;
}

TriangleMesh make_uv_sphere(double radius, int slices, int stacks) {
  require_positive(radius, "make_uv_sphere", "radius");
  require_at_least(slices, 3, "make_uv_sphere", "slices");
  require_at_least(stacks, 2, "make_uv_sphere", "stacks");
  require_int_indices(2 * static_cast<std::int64_t>(slices) * stacks, "make_uv_sphere");

  // North pole, stacks - 1 rings of `slices` vertices from north to south, south pole.
  const int num_rings = stacks - 1;
  const int north = 0;
  const int south = 1 + num_rings * slices;
  const auto ring_vertex = [&](int ring, int slice) { return 1 + ring * slices + slice % slices; };
  TriangleMesh mesh;
  mesh.positions.resize(3, south + 1);
  mesh.positions.col(north) = Vec3(0.0, radius, 0.0);
  mesh.positions.col(south) = Vec3(0.0, -radius, 0.0);
  for (int ring = 0; ring < num_rings; ++ring) {
    const double polar = pi * (ring + 1) / stacks;
    for (int s = 0; s < slices; ++s) {
      mesh.positions.col(ring_vertex(ring, s)) =
          point_around_y(radius * std::sin(polar), 2.0 * pi * s / slices, radius * std::cos(polar));
    }
  }

  // Fans at the poles, two triangles per quad between neighbouring rings.
  mesh.triangles.resize(3, 2 * slices * num_rings);
  int t = 0;
  for (int s = 0; s < slices; ++s) {
    mesh.triangles.col(t++) << north, ring_vertex(0, s), ring_vertex(0, s + 1);
  }
  for (int ring = 0; ring + 1 < num_rings; ++ring) {
    for (int s = 0; s < slices; ++s) {
      const int a = ring_vertex(ring, s), b = ring_vertex(ring, s + 1);
      const int c = ring_vertex(ring + 1, s + 1), d = ring_vertex(ring + 1, s);
      mesh.triangles.col(t++) << a, d, c;
      mesh.triangles.col(t++) << a, c, b;
    }
  }
  for (int s = 0; s < slices; ++s) {
    mesh.triangles.col(t++) << south, ring_vertex(num_rings - 1, s + 1), ring_vertex(num_rings - 1, s);
  }
  return mesh;
}

TriangleMesh make_box(const Vec3& half_extents) {
  require_positive(half_extents.x(), "make_box", "half_extents.x");
  require_positive(half_extents.y(), "make_box", "half_extents.y");
  require_positive(half_extents.z(), "make_box", "half_extents.z");

  // Corner c sits on the + side of x, y, z where bit 0, 1, 2 of c is set.
  TriangleMesh mesh;
  mesh.positions.resize(3, 8);
  for (int c = 0; c < 8; ++c) {
    mesh.positions.col(c) =
        Vec3((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0).cwiseProduct(half_extents);
  }

  // Two triangles per face, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
  const int faces[12][3] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                            {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  mesh.triangles.resize(3, 12);
  for (int t = 0; t < 12; ++t) mesh.triangles.col(t) << faces[t][0], faces[t][1], faces[t][2];
  return mesh;
}

TriangleMesh make_cylinder(double radius, double height, int segments, bool capped) {
  require_positive(radius, "make_cylinder", "radius");
  require_positive(height, "make_cylinder", "height");
  require_at_least(segments, 3, "make_cylinder", "segments");
  require_int_indices(4 * static_cast<std::int64_t>(segments), "make_cylinder");

  // Top ring, bottom ring, then (capped) the top and bottom cap centres.
  const auto top = [&](int s) { return s % segments; };
  const auto bottom = [&](int s) { return segments + s % segments; };
  const int top_centre = 2 * segments;
  const int bottom_centre = 2 * segments + 1;
  TriangleMesh mesh;
  mesh.positions.resize(3, capped ? 2 * segments + 2 : 2 * segments);
  for (int s = 0; s < segments; ++s) {
    const double angle = 2.0 * pi * s / segments;
    mesh.positions.col(top(s)) = point_around_y(radius, angle, 0.5 * height);
    mesh.positions.col(bottom(s)) = point_around_y(radius, angle, -0.5 * height);
  }
  if (capped) {
    mesh.positions.col(top_centre) = Vec3(0.0, 0.5 * height, 0.0);
    mesh.positions.col(bottom_centre) = Vec3(0.0, -0.5 * height, 0.0);
  }

  // Two triangles per side quad, then a fan on each cap.
  mesh.triangles.resize(3, capped ? 4 * segments : 2 * segments);
  int t = 0;
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.col(t++) << top(s), bottom(s), bottom(s + 1);
    mesh.triangles.col(t++) << top(s), bottom(s + 1), top(s + 1);
  }
  if (capped) {
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.col(t++) << top_centre, top(s), top(s + 1);
      mesh.triangles.col(t++) << bottom_centre, bottom(s + 1), bottom(s);
    }
  }
  return mesh;
}

}  // namespace weft
