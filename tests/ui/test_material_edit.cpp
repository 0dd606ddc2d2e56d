#include "ui/material_edit.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "ui/temp_scene_file.hpp"
#include "ui/simulation_session.hpp"

namespace weft {
namespace {

// A hanging cloth with every editable term on; `extra` adds keys to the cloth.
std::string hanging_cloth(const std::string& integrator, const std::string& extra = "") {
  return R"({
  "fps": 30,
  "solver": {"integrator": ")" + integrator + R"(", "time_step": 0.002},
  "cloths": [{
    "grid": {"size": [1, 1], "resolution": [6, 6]},
    "pins": {"corners": ["top_left", "top_right"]},
    "springs": {"structural": {"stiffness": 50, "damping": 0.01},
                "shear": {"stiffness": 20, "damping": 0.01},
                "bend": {"stiffness": 1, "damping": 0.001}})" + extra + R"(
  }]
})";
}

const char* const all_terms = R"(,
    "membrane": {"young_modulus": 2000, "poisson_ratio": 0.3, "thickness": 0.001},
    "bending": {"stiffness": 0.0001},
    "air_drag": {"normal": 0.5, "tangential": 0.05})";

// Lowest vertex height after `frames` frames.
double lowest_point(SimulationSession& session, int frames) {
  for (int f = 0; f < frames; ++f) session.advance_frame();
  return session.world().cloths()[0].state.x.row(1).minCoeff();
}

// Largest stretch |x_j - x_i| / rest length - 1 over the structural springs.
double largest_stretch(const Cloth& cloth) {
  const SpringSet& springs = cloth.model.springs;
  double largest = 0.0;
  for (int s = springs.kind_begin[0]; s < springs.kind_begin[1]; ++s) {
    const double length = (cloth.state.x.col(springs.vertices(1, s)) - cloth.state.x.col(springs.vertices(0, s))).norm();
    largest = std::max(largest, length / springs.rest_length[s] - 1.0);
  }
  return largest;
}

TEST(MaterialEdit, ReadThenApplyChangesNothing) {
  const TempSceneFile file(hanging_cloth("symplectic_euler", all_terms));
  SimulationSession session(file.path(), {});
  ClothModel& model = session.world().cloths()[0].model;
  const ClothModel before = model;
  apply_material(model, read_material(model));
  EXPECT_EQ(model.springs.stiffness, before.springs.stiffness);
  EXPECT_EQ(model.springs.damping, before.springs.damping);
  EXPECT_EQ(model.membrane.material.young_modulus, before.membrane.material.young_modulus);
  EXPECT_EQ(model.bending.stiffness, before.bending.stiffness);
  EXPECT_EQ(model.air_drag.normal_coefficient, before.air_drag.normal_coefficient);
  EXPECT_TRUE(model.mass.isApprox(before.mass));
}

TEST(MaterialEdit, WritesEveryEnabledTermIntoTheWorld) {
  const TempSceneFile file(hanging_cloth("symplectic_euler", all_terms));
  SimulationSession session(file.path(), {});
  ClothModel& model = session.world().cloths()[0].model;
  ClothMaterial material = read_material(model);
  material.springs.stiffness[static_cast<int>(SpringKind::shear)] = 77.0;
  material.springs.damping[static_cast<int>(SpringKind::bend)] = 0.125;
  material.membrane.young_modulus = 5000.0;
  material.membrane.poisson_ratio = 0.2;
  material.membrane.min_stretch = 0.5;
  material.bending_stiffness = 0.003;
  material.normal_drag = 2.0;
  material.wind = Vec3(1.0, 0.0, 0.0);
  material.area_density = 2.0 * read_material(model).area_density;
  const double mass_before = model.mass.sum();
  apply_material(model, material);

  const SpringSet& springs = model.springs;
  for (int s = springs.kind_begin[1]; s < springs.kind_begin[2]; ++s) EXPECT_EQ(springs.stiffness[s], 77.0);
  for (int s = springs.kind_begin[2]; s < springs.kind_begin[3]; ++s) EXPECT_EQ(springs.damping[s], 0.125);
  for (int s = springs.kind_begin[0]; s < springs.kind_begin[1]; ++s) EXPECT_EQ(springs.stiffness[s], 50.0);
  EXPECT_EQ(model.membrane.material.young_modulus, 5000.0);
  EXPECT_EQ(model.membrane.material.poisson_ratio, 0.2);
  EXPECT_EQ(model.membrane.material.min_stretch, 0.5);
  EXPECT_EQ(model.bending.stiffness, 0.003);
  EXPECT_EQ(model.air_drag.normal_coefficient, 2.0);
  EXPECT_TRUE(model.air_drag.wind.isApprox(Vec3(1.0, 0.0, 0.0)));
  EXPECT_NEAR(model.mass.sum(), 2.0 * mass_before, 1e-12);
  // Pins stay pinned; free vertices get the new inverse mass.
  for (int i = 0; i < model.inverse_mass.size(); ++i) {
    if (model.inverse_mass[i] != 0.0) {
      EXPECT_NEAR(model.inverse_mass[i] * model.mass[i], 1.0, 1e-12);
    }
  }
  EXPECT_EQ((model.inverse_mass.array() == 0.0).count(), 2);
}

TEST(MaterialEdit, TermsOffInTheSceneStayOff) {
  const TempSceneFile file(hanging_cloth("implicit_euler"));
  SimulationSession session(file.path(), {});
  ClothModel& model = session.world().cloths()[0].model;
  ClothMaterial material = read_material(model);
  material.bending_stiffness = 1.0;
  material.normal_drag = 1.0;
  material.membrane.young_modulus = 1e6;
  apply_material(model, material);
  EXPECT_FALSE(model.bending.enabled());
  EXPECT_FALSE(model.air_drag.enabled());
  EXPECT_FALSE(model.membrane.enabled());
  // ...so the implicit solver's Hessian pattern still fits and it keeps stepping.
  session.advance_frame();
  EXPECT_TRUE(session.error().empty()) << session.error();
}

// A live edit between steps changes how the running world moves: once the swinging has died
// down, springs made stiffer mid-run stretch less under the cloth's weight.
TEST(MaterialEdit, StifferSpringsWhileRunningStretchLess) {
  for (const char* integrator : {"symplectic_euler", "implicit_euler"}) {
    const TempSceneFile file(hanging_cloth(integrator, R"(, "mass_damping": 4)"));
    SimulationSession soft(file.path(), {}), stiff(file.path(), {});
    lowest_point(soft, 3);
    lowest_point(stiff, 3);
    ClothModel& model = stiff.world().cloths()[0].model;
    ClothMaterial material = read_material(model);
    for (double& k : material.springs.stiffness) k *= 8.0;
    apply_material(model, material);
    lowest_point(soft, 60);
    lowest_point(stiff, 60);
    const double soft_stretch = largest_stretch(soft.world().cloths()[0]);
    const double stiff_stretch = largest_stretch(stiff.world().cloths()[0]);
    EXPECT_GT(soft_stretch, 0.0) << integrator;
    EXPECT_LT(stiff_stretch, 0.5 * soft_stretch) << integrator;
    EXPECT_TRUE(stiff.error().empty()) << stiff.error();
  }
}

// The membrane's Young's modulus scales its elastic energy at the same positions.
TEST(MaterialEdit, YoungModulusScalesMembraneEnergy) {
  const TempSceneFile file(hanging_cloth("symplectic_euler", all_terms));
  SimulationSession session(file.path(), {});
  lowest_point(session, 10);
  const double before = session.world().energies().terms.membrane;
  ASSERT_GT(before, 0.0);
  ClothModel& model = session.world().cloths()[0].model;
  ClothMaterial material = read_material(model);
  material.membrane.young_modulus *= 3.0;
  apply_material(model, material);
  EXPECT_NEAR(session.world().energies().terms.membrane, 3.0 * before, 1e-9 * before);
}

// The solver panel switches integrators between steps of a running world.
TEST(MaterialEdit, IntegratorSwitchWhileRunningKeepsStepping) {
  const TempSceneFile file(hanging_cloth("symplectic_euler", all_terms));
  SimulationSession session(file.path(), {});
  session.playing = true;
  lowest_point(session, 2);
  session.world().settings.integrator = IntegratorKind::implicit_euler;
  session.advance_frame();
  EXPECT_GT(session.world().last_step_stats().newton_iterations, 0);
  session.world().settings.integrator = IntegratorKind::explicit_midpoint;
  session.set_max_time_step(0.001);
  session.advance_frame();
  EXPECT_EQ(session.world().last_step_stats().newton_iterations, 0);
  EXPECT_NEAR(session.world().time(), 4.0 / 30.0, 1e-12);
  EXPECT_TRUE(session.world().cloths()[0].state.x.allFinite());
  EXPECT_TRUE(session.error().empty()) << session.error();
}

}  // namespace
}  // namespace weft
