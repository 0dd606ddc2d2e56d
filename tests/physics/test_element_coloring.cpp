// The coloured parallel evaluation of element terms (physics/element_coloring.hpp): patches of
// one colour share no vertex, and the energy, gradient and Hessian it assembles equal the serial
// element-by-element ones and do not depend on the thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A 40x40 cloth (3042 triangles, ~4500 hinges: dozens of patches) with membrane and bending,
// its vertices shaken so that every element has stress.
struct ShakenCloth {
  ClothModel model;
  Positions x;
};

ShakenCloth shaken_cloth() {
  const auto document = nlohmann::json::parse(R"({
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [40, 40], "triangulation": "alternating"},
      "density": 0.2,
      "membrane": {"young_modulus": 1e5, "poisson_ratio": 0.3, "thickness": 1e-3, "compression_factor": 0.1},
      "bending": {"stiffness": 1e-3}
    }]
  })");
  World world = build_world(parse_scene(document, "<inline>"));
  ShakenCloth cloth{world.cloths()[0].model, world.cloths()[0].state.x};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> shake(-3e-3, 3e-3);
  for (Eigen::Index k = 0; k < cloth.x.size(); ++k) cloth.x.data()[k] += shake(random);
  return cloth;
}

struct Assembled {
  double energy;
  Positions gradient;
  Eigen::VectorXd hessian_values;
};

Assembled assemble(const ClothModel& model, const Positions& x, bool project) {
  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  hessian.set_zero();
  Positions gradient = Positions::Zero(3, x.cols());
  const double energy =
      evaluate_potential(model, Vec3(0, -9.81, 0), x, &gradient, &hessian, stencils, project);
  hessian.finish_assembly();
  const auto& values = hessian.matrix();
  return {energy, gradient, Eigen::Map<const Eigen::VectorXd>(values.valuePtr(), values.nonZeros())};
}

template <int K>
void expect_patches_of_a_color_share_no_vertex(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements,
                                               const ElementColoring& coloring) {
  ASSERT_GT(coloring.num_colors(), 1);
  // For every vertex, the patches that touch it: any two different ones must differ in colour.
  std::vector<std::set<int>> patches_at(elements.maxCoeff() + 1);
  for (int e = 0; e < elements.cols(); ++e) {
    for (int k = 0; k < K; ++k) patches_at[elements(k, e)].insert(coloring.patch_of(e));
  }
  int checked = 0;
  for (const std::set<int>& patches : patches_at) {
    for (const int a : patches) {
      for (const int b : patches) {
        if (a == b) continue;
        EXPECT_NE(coloring.color_of_patch(a), coloring.color_of_patch(b)) << "patches " << a << " and " << b;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 0);  // patches do meet at vertices, so the test tested something
}

TEST(ElementColoring, PatchesOfOneColourShareNoVertex) {
  const ShakenCloth cloth = shaken_cloth();
  expect_patches_of_a_color_share_no_vertex(cloth.model.triangles, cloth.model.membrane.coloring);
  expect_patches_of_a_color_share_no_vertex(cloth.model.bending.hinges, cloth.model.bending.coloring);
}

TEST(ElementColoring, ParallelAssemblyEqualsSerialAndIsTheSameAtOneAndTwoThreads) {
  const ShakenCloth cloth = shaken_cloth();
  ClothModel serial_model = cloth.model;
  serial_model.membrane.coloring = ElementColoring();  // no colouring: elements in order, one thread
  serial_model.bending.coloring = ElementColoring();
  const int threads_before = omp_get_max_threads();
  for (const bool project : {false, true}) {
    omp_set_num_threads(1);
    const Assembled one = assemble(cloth.model, cloth.x, project);
    omp_set_num_threads(2);
    const Assembled two = assemble(cloth.model, cloth.x, project);
    const Assembled serial = assemble(serial_model, cloth.x, project);
    EXPECT_EQ(one.energy, two.energy);
    EXPECT_TRUE(one.gradient == two.gradient);
    EXPECT_TRUE(one.hessian_values == two.hessian_values);
    // Only the summation order differs from the serial loop.
    EXPECT_NEAR(one.energy, serial.energy, 1e-12 * std::abs(serial.energy));
    EXPECT_LE((one.gradient - serial.gradient).cwiseAbs().maxCoeff(),
              1e-12 * serial.gradient.cwiseAbs().maxCoeff());
    EXPECT_LE((one.hessian_values - serial.hessian_values).cwiseAbs().maxCoeff(),
              1e-12 * serial.hessian_values.cwiseAbs().maxCoeff());
    EXPECT_GT(serial.gradient.cwiseAbs().maxCoeff(), 0.0);
  }
  omp_set_num_threads(threads_before);
}

}  // namespace
}  // namespace weft
