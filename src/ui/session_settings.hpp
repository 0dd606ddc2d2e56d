#pragma once
// What the viewer's panels edit on a SimulationSession, as one value: solver settings, the largest
// time step, each cloth's material and contact material, the colliders' friction, pausing on
// contact and the dragged vertex. The panels edit a drawn copy of the session; these values carry
// the edits to the session that steps. No ImGui here.
#include <utility>
#include <vector>

#include "ui/material_edit.hpp"
#include "ui/simulation_session.hpp"
#include "ui/vertex_drag.hpp"

namespace weft {

struct SessionSettings {
  int generation = 0;  // the session's generation they were read from; another world ignores them
  SolverSettings solver;
  double max_time_step = 0.0;
  std::vector<ClothMaterial> materials;                      // per cloth (the area density aside: masses)
  std::vector<Eigen::VectorXd> masses;                       // per cloth, per vertex (kg), copied as they are
  std::vector<ContactMaterial> contact;                      // per cloth
  std::vector<std::pair<double, double>> collider_friction;  // per collider: static, kinetic
  bool pause_on_contact = false;
  VertexDrag drag;
};

bool operator==(const ClothMaterial& a, const ClothMaterial& b);
inline bool operator!=(const ClothMaterial& a, const ClothMaterial& b) { return !(a == b); }

SessionSettings read_settings(const SimulationSession& session, const VertexDrag& drag);

// Writes `settings` into `session` if they were read from its generation (returns whether). A
// material is written only where it differs from the cloth's, so settings applied again change
// nothing; the drag is left to the caller.
bool apply_settings(SimulationSession& session, const SessionSettings& settings);

}  // namespace weft
