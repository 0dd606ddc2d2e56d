#pragma once
// Draws registered triangle meshes with two-sided lighting over a gradient background, then a
// debug overlay of lines and points. Register a mesh once, then push new positions (normals are
// recomputed) or a new placement whenever they change. Shaders are files, reloadable while
// running. Needs a current GL context from construction to destruction.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/math.hpp"
#include "render/debug_overlay.hpp"
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

// How one mesh is shown, beyond its surface colours.
struct MeshDisplay {
  bool visible = true;
  bool wireframe = false;       // its edges as lines over the surface
  bool heat_map = false;        // colour by the vertex scalars instead of the style's colours
  float scalar_range = 0.1f;    // heat map: |scalar| shown at full colour
  bool cull_front = false;      // draw only the faces turned away from the camera (cutaway)
};

using MeshHandle = int;

class Renderer {
 public:
  // Loads mesh, background and overlay shaders (.vert/.frag) from `shader_dir`; throws RenderError.
  explicit Renderer(const std::string& shader_dir);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Vertical background gradient.
  Eigen::Vector3f background_top{0.17f, 0.18f, 0.21f};
  Eigen::Vector3f background_bottom{0.05f, 0.05f, 0.06f};
  Eigen::Vector3f wireframe_color{0.08f, 0.08f, 0.1f};

  // Registers a mesh with the vertex positions it starts at (3 x n_vertices); placed at identity.
  MeshHandle add_mesh(const Triangles& triangles, const Positions& positions, const SurfaceStyle& style);
  // New vertex positions of the same mesh (3 x n_vertices); its normals are recomputed from them.
  void update_positions(MeshHandle mesh, const Positions& positions);
  // New vertex scalars for the heat map (n_vertices).
  void update_scalars(MeshHandle mesh, const Eigen::VectorXd& scalars);
  // Rigid placement of the mesh's vertices in the world.
  void set_transform(MeshHandle mesh, const Eigen::Isometry3d& transform);
  void set_display(MeshHandle mesh, const MeshDisplay& display);
  // Forgets every mesh (e.g. before registering a reloaded scene).
  void clear();

  // Recompiles the shaders from their files. On failure keeps the current ones and returns the
  // compiler's message; returns an empty string on success.
  std::string reload_shaders();

  // Clears and draws the background, every visible mesh and `overlay` into the current
  // framebuffer's viewport. `pixel_scale` is framebuffer pixels per window unit (high-DPI point sizes).
  void draw(const OrbitCamera& camera, int framebuffer_width, int framebuffer_height,
            const DebugOverlay& overlay = {}, float pixel_scale = 1.0f);

 private:
  struct Entry {
    GpuMesh gpu;
    Triangles triangles;  // (3 x n_triangles), kept for recomputing normals
    SurfaceStyle style;
    MeshDisplay display;
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    Eigen::Matrix3Xf positions;  // upload scratch (3 x n_vertices)
    Eigen::Matrix3Xf normals;    // upload scratch (3 x n_vertices)
  };
  struct Programs {
    ShaderProgram mesh, background, overlay;
  };
  static std::unique_ptr<Programs> load_programs(const std::string& shader_dir);
  void draw_overlay(const DebugOverlay& overlay, const Eigen::Matrix4f& view_projection, float pixel_scale);

  std::string shader_dir_;
  std::unique_ptr<Programs> programs_;
  unsigned int empty_vertex_array_ = 0;  // core profile needs a bound VAO even without attributes
  unsigned int overlay_vertex_array_ = 0;
  unsigned int overlay_buffer_ = 0;
  std::vector<float> overlay_scratch_;   // interleaved x y z r g b size
  std::vector<Entry> meshes_;
};

}  // namespace weft
