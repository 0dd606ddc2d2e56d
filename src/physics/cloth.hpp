#pragma once
// A cloth: what stays fixed during a run (ClothModel) apart from what the step changes (ClothState).
#include <string>

#include "core/math.hpp"
#include "physics/air_drag.hpp"
#include "physics/bending.hpp"
#include "physics/mass_spring.hpp"
#include "physics/membrane_stvk.hpp"
#include "physics/scripted_pins.hpp"
#include "physics/volume_pressure.hpp"

namespace weft {

struct ClothModel {
  std::string name;
  Triangles triangles;             // (3 x n_triangles)
  Eigen::Matrix2Xd uvs;            // (2 x n_vertices) or empty
  Positions rest_positions;        // (3 x n_vertices)
  Eigen::VectorXd mass;            // lumped vertex masses, kg (n_vertices)
  Eigen::VectorXd inverse_mass;    // 0 for pinned vertices (n_vertices)
  // Force terms; each is off (and costs nothing) unless the scene turned it on.
  SpringSet springs;               // mass-spring structural, shear and bend springs (Provot 1995)
  MembraneTerm membrane;           // StVK triangle membrane with buckling and plastic yield
  BendingTerm bending;             // hinge bending, dihedral or quadratic
  AirDragTerm air_drag;            // air drag and wind
  PressureTerm pressure;           // enclosed-volume pressure (closed soft bodies)
  std::vector<PinScript> scripted_pins;  // moving pins (their vertices have inverse_mass 0)
  double thickness = 0.005;        // m
  double mass_damping = 0.0;       // 1/s, Rayleigh mass damping coefficient (0: off)
  int grid_nx = 0, grid_ny = 0;    // lattice size when made from a grid, else 0
};

struct ClothState {
  Positions x;                     // positions (3 x n_vertices)
  Positions v;                     // velocities (3 x n_vertices)
  Positions force;                 // scratch: total force of the current evaluation (3 x n_vertices)
};

struct Cloth {
  ClothModel model;
  ClothState state;
  int num_vertices() const { return static_cast<int>(state.x.cols()); }
};

// A cloth at rest at `rest_positions`, state allocated once here.
Cloth make_cloth(ClothModel model);

}  // namespace weft
