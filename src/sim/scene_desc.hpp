#pragma once
// What a scene file describes, as plain data. The defaults here are the scene-file defaults:
// docs/scenes.md documents every field, io/scene_file.cpp reads and writes them.
#include <string>
#include <vector>

#include "collision/collider.hpp"
#include "core/mesh_generators.hpp"
#include "physics/adaptive_stepping.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/integrator.hpp"

namespace weft {

// Stiffness (N/m) and damping (N s/m) of one kind of spring, per spring, as in the seed formula.
struct SpringParams {
  double stiffness = 0.0;
  double damping = 0.0;
};

struct ClothDesc {
  std::string name = "cloth";

  // Shape: a grid (when obj_file is empty) or a triangle mesh from an OBJ file.
  double grid_width = 2.0;        // m, along local x
  double grid_height = 2.0;       // m, along local y
  int grid_nx = 32;               // vertices along local x
  int grid_ny = 32;               // vertices along local y
  GridTriangulation triangulation = GridTriangulation::alternating;
  std::string obj_file;           // resolved relative to the scene file's folder

  // Placement: x -> R(rotation_degrees) * (scale * x) + translation.
  Vec3 translation = Vec3::Zero();
  Vec3 rotation_degrees = Vec3::Zero();
  double scale = 1.0;

  // Mass: area density, or a total mass spread over the vertices like area density (mass > 0 wins).
  double density = 0.2;           // kg/m^2
  double mass = 0.0;              // kg; 0 means "use density"

  SpringParams structural{2000.0, 0.5};
  SpringParams shear{500.0, 0.2};
  SpringParams bend{50.0, 0.05};

  double thickness = 0.005;       // m, contact offset from colliders
  double mass_damping = 0.0;      // 1/s, damps every vertex velocity: f = -c m v

  // Pins: vertex indices, named grid corners ("top_left", ...) and grid edges ("top", ...).
  std::vector<int> pin_vertices;
  std::vector<std::string> pin_corners;
  std::vector<std::string> pin_edges;
};

struct SceneDesc {
  std::string source_file;        // where it came from, for error messages ("<inline>" if none)
  std::string name = "untitled";
  Vec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  IntegratorKind integrator = IntegratorKind::symplectic_euler;
  double time_step = 1.0 / 600.0; // s, the largest step; each frame is cut into equal steps <= this
  int substeps = 1;               // integration sub-steps per time step
  ImplicitEulerSettings implicit; // "solver": {"newton": ...}
  AdaptiveSettings adaptive;      // "solver": {"adaptive": ...}
  double fps = 30.0;              // recorded frames per simulated second
  int frames = 90;                // frames to simulate (the initial state is frame 0)
  std::vector<ClothDesc> cloths;
  std::vector<Collider> colliders;
};

}  // namespace weft
