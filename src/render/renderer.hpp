#pragma once
// Draws registered triangle meshes with two-sided lighting over a gradient background.
// Register a mesh once, then push new positions (normals are recomputed) or a new placement
// whenever they change. Needs a current GL context from construction to destruction.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/math.hpp"
#include "render/gpu_mesh.hpp"
#include "render/orbit_camera.hpp"
#include "render/shader.hpp"

namespace weft {

// Colours (linear RGB in [0, 1]) of a surface's front (counter-clockwise) and back faces.
struct SurfaceStyle {
  Eigen::Vector3f front_color{0.8f, 0.8f, 0.8f};
  Eigen::Vector3f back_color{0.8f, 0.8f, 0.8f};
  float specular = 0.15f;     // strength of the white highlight
  float shininess = 32.0f;    // Blinn exponent
  float checker_size = 0.0f;  // m; > 0 draws a faint checkerboard in the mesh's own frame
};

using MeshHandle = int;

class Renderer {
 public:
  // Loads mesh.vert/.frag and background.vert/.frag from `shader_dir`; throws RenderError.
  explicit Renderer(const std::string& shader_dir);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Vertical background gradient.
  Eigen::Vector3f background_top{0.17f, 0.18f, 0.21f};
  Eigen::Vector3f background_bottom{0.05f, 0.05f, 0.06f};

  // Registers a mesh with the vertex positions it starts at (3 x n_vertices); placed at identity.
  MeshHandle add_mesh(const Triangles& triangles, const Positions& positions, const SurfaceStyle& style);
  // New vertex positions of the same mesh (3 x n_vertices); its normals are recomputed from them.
  void update_positions(MeshHandle mesh, const Positions& positions);
  // Rigid placement of the mesh's vertices in the world.
  void set_transform(MeshHandle mesh, const Eigen::Isometry3d& transform);
  // Forgets every mesh (e.g. before registering a reloaded scene).
  void clear();

  // Clears and draws the background and every mesh into the current framebuffer's viewport.
  void draw(const OrbitCamera& camera, int framebuffer_width, int framebuffer_height) const;

 private:
  struct Entry {
    GpuMesh gpu;
    Triangles triangles;  // (3 x n_triangles), kept for recomputing normals
    SurfaceStyle style;
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    Eigen::Matrix3Xf positions;  // upload scratch (3 x n_vertices)
    Eigen::Matrix3Xf normals;    // upload scratch (3 x n_vertices)
  };

  ShaderProgram mesh_program_;
  ShaderProgram background_program_;
  unsigned int empty_vertex_array_ = 0;  // core profile needs a bound VAO even without attributes
  std::vector<Entry> meshes_;
};

}  // namespace weft
