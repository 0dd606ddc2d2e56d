#pragma once
// Ray picking of cloth vertices under the mouse. Plain math, no OpenGL.
#include <optional>
#include <vector>

#include "collision/bvh.hpp"
#include "core/math.hpp"
#include "physics/cloth.hpp"
#include "render/orbit_camera.hpp"

namespace weft {

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit
};

// The ray from the eye through a point of the viewport in normalised device coordinates
// (x right, y up, both in [-1, 1]) for a viewport of aspect width / height.
Ray camera_ray(const OrbitCamera& camera, double aspect, double ndc_x, double ndc_y);

struct VertexPick {
  int cloth = -1;
  int vertex = -1;
  double distance = 0.0;  // m along the ray to the hit point on the surface
  Vec3 hit = Vec3::Zero();
};

// The nearest cloth triangle the ray crosses (either side), and its corner nearest the hit point.
// With `bvhs` (one per cloth, built or refitted on the positions in `cloths`), only the triangles
// in boxes the ray enters are tested, nearest box first; a cloth whose hierarchy does not match
// its mesh is tested triangle by triangle.
std::optional<VertexPick> pick_vertex(const std::vector<Cloth>& cloths, const Ray& ray,
                                      const std::vector<Bvh>* bvhs = nullptr);

// Where the ray meets the plane through `point` facing the camera's view direction: the drag target
// that keeps a grabbed vertex at its depth.
Vec3 point_on_view_plane(const Ray& ray, const Vec3& point, const Vec3& view_direction);

}  // namespace weft
