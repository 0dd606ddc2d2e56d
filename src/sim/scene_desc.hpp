#pragma once
// What a scene file describes, as plain data. The defaults here are the scene-file defaults:
// docs/scenes.md documents every field, io/scene_file.cpp reads and writes them.
#include <string>
#include <vector>

#include "collision/collider.hpp"
#include "core/mesh_generators.hpp"
#include "physics/adaptive_stepping.hpp"
#include "physics/bending.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/xpbd.hpp"
#include "physics/integrator.hpp"
#include "physics/membrane_stvk.hpp"
#include "sim/collision_phase.hpp"

namespace weft {

// Stiffness (N/m) and damping (N s/m) of one kind of spring, per spring, as in mass_spring.hpp.
struct SpringParams {
  double stiffness = 0.0;
  double damping = 0.0;
};

// Vertices picked by index, by named grid corner ("top_left", ...) and by grid edge ("top", ...).
struct PinSelection {
  std::vector<int> vertices;
  std::vector<std::string> corners;
  std::vector<std::string> edges;
  bool empty() const { return vertices.empty() && corners.empty() && edges.empty(); }
};

// Pinned vertices that move rigidly (physics/scripted_pins.hpp): translation plus rotation about
// an axis through `center`.
struct MovingPinDesc {
  PinSelection selection;
  Vec3 velocity = Vec3::Zero();          // m/s
  Vec3 center = Vec3::Zero();            // m
  Vec3 axis = Vec3::UnitY();             // normalised on load
  double angular_velocity_degrees = 0.0; // degrees/s
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
  bool sphere = false;            // a closed UV sphere instead (soft bodies)
  double sphere_radius = 0.5;     // m
  int sphere_slices = 24;         // around the Y axis
  int sphere_stacks = 12;         // pole to pole

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

  // Continuum terms, each off unless the scene has its key.
  bool membrane = false;
  MembraneMaterial membrane_material{5e6, 0.3, 5e-4, 0.1};  // Pa, -, m, compression factor
  double yield_strain = 0.0;      // plastic yield: principal Green strain limit
  double plastic_flow = 0.0;      // fraction of the excess absorbed per step (0: elastic)
  bool bending = false;
  double bending_stiffness = 5e-5;  // J
  BendingModel bending_model = BendingModel::dihedral;
  double normal_drag = 0.0;       // kg/(m^2 s)
  double tangential_drag = 0.0;   // kg/(m^2 s)
  bool pressure = false;
  double bulk_modulus = 1e4;      // Pa
  double pressure_scale = 1.0;    // target volume / rest volume

  double thickness = 0.005;       // m, contact distance kept from colliders and other cloth
  ContactMaterial contact;        // friction coefficients, self-collision on/off
  Vec3 initial_velocity = Vec3::Zero();  // m/s, every vertex that is not pinned, at time 0
  double mass_damping = 0.0;      // 1/s, damps every vertex velocity: f = -c m v

  PinSelection pins;                      // fixed vertices
  std::vector<MovingPinDesc> moving_pins; // scripted vertices
};

// Bounds the scene reader holds every scene to (docs/scenes.md).
constexpr int max_frames = 10'000'000;  // frames of one run
constexpr double min_fps = 1.0;         // frames per simulated second
constexpr double max_fps = 10'000.0;
// A cloth's contact thickness at most this fraction of its size (its rest bounding-box diagonal):
// beyond it every part of the cloth is "in contact" with most others and a step never ends.
constexpr double max_thickness_fraction = 0.1;

// How the viewer opens the scene ("view"): where the camera looks from and what is displayed.
// Plain data with no effect on the simulation; the viewer translates it (app/viewer.cpp).
struct SceneView {
  bool has_target = false;
  Vec3 target = Vec3::Zero();      // m, the point the camera orbits; else the scene's centre
  double distance = 0.0;           // m, eye to target; 0: far enough to see the whole scene
  double yaw_degrees = 23.0;       // about +y: 0 puts the eye on +z looking along -z, 90 on +x
  double pitch_degrees = 17.0;     // above the horizontal, in [-88, 88]
  std::vector<std::string> show;   // display switches, as --show names them, applied in order
  double impulse_scale = 200.0;    // m of contact arrow per N s of impulse
  double max_arrow_length = 0.1;   // the longest contact arrow, as a fraction of the scene's size
};

struct SceneDesc {
  std::string source_file;        // where it came from, for error messages ("<inline>" if none)
  std::string name = "untitled";
  Vec3 gravity{0.0, -9.81, 0.0};  // m/s^2
  Vec3 wind = Vec3::Zero();       // m/s, the air's velocity (cloths with air_drag feel it)
  IntegratorKind integrator = IntegratorKind::symplectic_euler;
  double time_step = 1.0 / 600.0; // s, the largest step; each frame is cut into equal steps <= this
  int substeps = 1;               // integration sub-steps per time step
  double max_travel_edges = 0.0;  // "solver": {"max_travel_edges"}: SolverSettings::max_travel_edges
  ImplicitEulerSettings implicit; // "solver": {"newton": ...}
  XpbdSettings xpbd;              // "solver": {"xpbd": ...}
  AdaptiveSettings adaptive;      // "solver": {"adaptive": ...}
  double fps = 30.0;              // recorded frames per simulated second
  int frames = 90;                // frames to simulate (the initial state is frame 0)
  std::vector<ClothDesc> cloths;
  std::vector<Collider> colliders;
  CollisionSettings collision;    // "collision": {...}
  SceneView view;                 // "view": {...}, the viewer's only
};

}  // namespace weft
