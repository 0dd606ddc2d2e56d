#include <imgui.h>

#include <algorithm>

#include "ui/panels.hpp"

namespace weft {

namespace {

bool input_double(const char* label, double& value, double min_value, const char* format = "%.3g") {
  if (!ImGui::InputDouble(label, &value, 0.0, 0.0, format, ImGuiInputTextFlags_EnterReturnsTrue)) return false;
  value = std::max(value, min_value);
  return true;
}

}  // namespace

void draw_solver_panel(SimulationSession& session) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 190.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(440.0f, 0.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Solver")) {
    ImGui::End();
    return;
  }
  ImGui::PushItemWidth(220.0f);  // room for the labels with their units
  SolverSettings& settings = session.world().settings;
  // Switching integrators between steps is safe: each keeps its own storage per cloth.
  const IntegratorKind kinds[] = {IntegratorKind::symplectic_euler, IntegratorKind::midpoint_euler_cromer,
                                  IntegratorKind::explicit_midpoint, IntegratorKind::implicit_euler,
                                  IntegratorKind::xpbd};
  if (ImGui::BeginCombo("integrator", to_string(settings.integrator))) {
    for (IntegratorKind kind : kinds) {
      if (ImGui::Selectable(to_string(kind), kind == settings.integrator)) settings.integrator = kind;
    }
    ImGui::EndCombo();
  }
  // The largest step h, on a log scale from 10 us to one frame.
  const float frame_time = static_cast<float>(1.0 / session.scene().fps);
  float max_time_step = static_cast<float>(session.max_time_step());
  if (ImGui::SliderFloat("h (s)", &max_time_step, 1e-5f, frame_time, "%.2e",
                         ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoRoundToFormat)) {
    session.set_max_time_step(std::clamp(static_cast<double>(max_time_step), 1e-5, 1.0 / session.scene().fps));
  }
  ImGui::Text("%d steps of %.3g s per frame", session.schedule().steps_per_frame, session.schedule().time_step);
  ImGui::SliderInt("substeps", &settings.substeps, 1, 16);

  if (ImGui::TreeNodeEx("Newton (implicit Euler)", ImGuiTreeNodeFlags_DefaultOpen)) {
    input_double("tolerance (m/s)", settings.implicit.newton_tolerance, 1e-12, "%.2e");
    // At or above resting_start_residual() a step may end off by gravity's whole pull; the scene
    // file refuses such a tolerance, here h and the tolerance change live.
    const double gravity_velocity =
        resting_start_residual(settings.gravity, settings.time_step / settings.substeps);
    if (gravity_velocity > 0.0 && settings.implicit.newton_tolerance >= gravity_velocity) {
      ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.2f, 1.0f),
                         "at or above |g| h = %.2e m/s: steps may miss gravity's pull", gravity_velocity);
    }
    ImGui::SliderInt("max iterations", &settings.implicit.max_newton_iterations, 1, 100);
    int solver = settings.implicit.linear_solver == LinearSolverKind::cholesky ? 1 : 0;
    if (ImGui::Combo("linear solver", &solver, "conjugate gradient\0Cholesky\0")) {
      settings.implicit.linear_solver = solver == 1 ? LinearSolverKind::cholesky : LinearSolverKind::conjugate_gradient;
    }
    if (settings.implicit.linear_solver == LinearSolverKind::conjugate_gradient) {
      // Takes effect at the next solve (the Gauss-Seidel split is made on its first use).
      int preconditioner = settings.implicit.cg_preconditioner == Preconditioner::block_jacobi ? 1 : 0;
      if (ImGui::Combo("CG preconditioner", &preconditioner, "symmetric Gauss-Seidel\0block Jacobi\0")) {
        settings.implicit.cg_preconditioner =
            preconditioner == 1 ? Preconditioner::block_jacobi : Preconditioner::symmetric_gauss_seidel;
      }
    }
    input_double("CG tolerance", settings.implicit.cg_tolerance, 1e-14, "%.2e");
    ImGui::TreePop();
  }
  if (ImGui::TreeNodeEx("XPBD", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::SliderInt("XPBD substeps", &settings.xpbd.substeps, 1, 64);
    ImGui::SliderInt("XPBD iterations", &settings.xpbd.iterations, 1, 64);
    ImGui::TreePop();
  }
  if (ImGui::TreeNodeEx("Adaptive stepping (explicit)", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Checkbox("enabled", &settings.adaptive.enabled);
    input_double("error tolerance (m)", settings.adaptive.tolerance, 1e-12, "%.2e");
    input_double("h min (s)", settings.adaptive.h_min, 1e-9, "%.2e");
    input_double("h max (s)", settings.adaptive.h_max, settings.adaptive.h_min, "%.2e");
    ImGui::TreePop();
  }
  const StepStats& stats = session.world().last_step_stats();
  ImGui::Text("last step: %d Newton, %d CG iterations, residual %.2e m/s%s", stats.newton_iterations,
              stats.linear_iterations, stats.residual, stats.unconverged_steps > 0 ? " (unconverged)" : "");
  ImGui::Text("adaptive: %d accepted, %d rejected%s", stats.accepted_steps, stats.rejected_steps,
              stats.unmet_tolerance_steps > 0 ? ", tolerance not met at h min" : "");
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace weft
