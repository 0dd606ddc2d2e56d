// Vertex Block Descent (Chen et al. 2024) against Newton + CG on one implicit Euler step of the
// drape's cloth, without contact: how many sweeps VBD needs on Weft's stiff membrane (stiff
// elasticity is VBD's known weakness) and what a sweep costs. The state is the 64x64 drape after
// `--frames` frames of the full pipeline (folded on the sphere); from it one step of h = 1/240 s
// is solved for the cloth alone (no collider, no contact), by
//   newton   ImplicitEulerSolver capped at k = 1, 2, ... iterations (the shipped CG path),
//   vbd      per-vertex 3x3 Newton updates in vertex-colour order (Gauss-Seidel), each vertex's
//            block of the inertia, membrane (PSD-projected), hinge (Gauss-Newton) and damping
//            terms, optionally Chebyshev-accelerated (--rho), from the inertial predictor.
// Printed: method, iteration, seconds so far, residual (m/s, newton_residual of the full
// incremental potential's gradient). A first prototype, written for the measurement: each
// vertex evaluates its triangles' and hinges' full element matrices and keeps one block.
// --polish instead runs Newton capped at k = 3..8 iterations and then either sweeps of the same
// updates or restricted Newton iterations (exact solves of the Hessian's rows and columns of the
// region, the rest held) over only the vertices whose residual is above the scene's tolerance
// and their neighbours, printing per sweep or iteration how many are above, the region's size
// and the residual: whether the tail of a step's residual is local enough for local work to
// finish it. Rows "frozen_after_newton_k" repeat the restricted iterations for k = 4..11 with the
// Hessian of the first restricted iteration kept (no line search in either).
//   cmake --build build/release --target weft_vbd_membrane
//   build/release/bench/weft_vbd_membrane [--resolution 64] [--frames 20] [--sweeps 200] [--rho 0.9]
//   [--polish]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/SparseCholesky>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/hinge_bending.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/membrane_stvk.hpp"
#include "physics/sparse_hessian.hpp"
#include "sim/world.hpp"

namespace {

using namespace weft;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The step from `start` by the shipped Newton + CG capped at k iterations (no tolerance stop).
Cloth newton_capped(const Cloth& start, const World& world, int k) {
  Cloth cloth = start;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings = world.settings.implicit;
  settings.max_newton_iterations = k;
  settings.newton_tolerance = 1e-12;
  solver.step(cloth, world.settings.gravity, world.settings.time_step, settings);
  return cloth;
}

// The incremental potential's residual at x (as ImplicitEulerSolver measures it).
double residual_at(const ClothModel& model, const Vec3& gravity, const Positions& x, const Positions& x_start,
                   const Positions& x_hat, double h, Positions& gradient) {
  gradient.setZero(3, x.cols());
  evaluate_mass_quadratic(model.mass, 1.0 / (h * h), x, x_hat, &gradient, nullptr);
  evaluate_potential(model, gravity, x, &gradient, nullptr, HessianStencils{}, false);
  evaluate_dissipation(model, x_start, x, h, &gradient, nullptr, HessianStencils{});
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (model.inverse_mass[i] == 0.0) gradient.col(i).setZero();
  }
  return newton_residual(gradient, model.inverse_mass, h);
}

// Per vertex: the vertices that share a triangle or a hinge with it.
std::vector<std::vector<int>> vertex_neighbours(const ClothModel& model) {
  const int n = static_cast<int>(model.rest_positions.cols());
  std::vector<std::vector<int>> neighbours(n);
  const auto connect = [&](const int* v, int k) {
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b < k; ++b) {
        if (a != b) neighbours[v[a]].push_back(v[b]);
      }
    }
  };
  for (Eigen::Index t = 0; t < model.triangles.cols(); ++t) connect(model.triangles.col(t).data(), 3);
  for (Eigen::Index e = 0; e < model.bending.hinges.cols(); ++e) connect(model.bending.hinges.col(e).data(), 4);
  return neighbours;
}

// Vertex colours such that no two vertices of one triangle or hinge share one (greedy).
std::vector<std::vector<int>> colour_vertices(const ClothModel& model) {
  const int n = static_cast<int>(model.rest_positions.cols());
  const std::vector<std::vector<int>> neighbours = vertex_neighbours(model);
  std::vector<int> colour(n, -1);
  int colours = 0;
  for (int v = 0; v < n; ++v) {
    std::vector<char> used(colours + 1, 0);
    for (const int w : neighbours[v]) {
      if (colour[w] >= 0) used[colour[w]] = 1;
    }
    int c = 0;
    while (used[c]) ++c;
    colour[v] = c;
    colours = std::max(colours, c + 1);
  }
  std::vector<std::vector<int>> groups(colours);
  for (int v = 0; v < n; ++v) groups[colour[v]].push_back(v);
  return groups;
}

struct Incidence {
  std::vector<std::vector<std::pair<int, int>>> triangles;  // per vertex: (triangle, corner)
  std::vector<std::vector<std::pair<int, int>>> hinges;     // per vertex: (hinge, slot)
};

Incidence incidence(const ClothModel& model) {
  const int n = static_cast<int>(model.rest_positions.cols());
  Incidence inc{std::vector<std::vector<std::pair<int, int>>>(n), std::vector<std::vector<std::pair<int, int>>>(n)};
  for (int t = 0; t < model.triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) inc.triangles[model.triangles(k, t)].push_back({t, k});
  }
  for (int e = 0; e < model.bending.hinges.cols(); ++e) {
    for (int k = 0; k < 4; ++k) inc.hinges[model.bending.hinges(k, e)].push_back({e, k});
  }
  return inc;
}

// One Gauss-Seidel sweep of per-vertex Newton updates over the colours.
void vbd_sweep(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
               const Positions& x_hat, const std::vector<std::vector<int>>& colours, const Incidence& inc,
               Positions& x, const std::vector<char>* active = nullptr) {
  const double inertia = 1.0 / (h * h);
  const double damping = model.mass_damping / h;
  for (const std::vector<int>& group : colours) {
    for (const int i : group) {
      if (model.inverse_mass[i] == 0.0 || (active != nullptr && !(*active)[i])) continue;
      const double m = model.mass[i];
      Vec3 g = m * inertia * (x.col(i) - x_hat.col(i)) - m * gravity + m * damping * (x.col(i) - x_start.col(i));
      Mat3 hess = (m * (inertia + damping)) * Mat3::Identity();
      for (const auto& [t, k] : inc.triangles[i]) {
        Vector9d tg;
        Matrix9d th;
        membrane_energy(x.col(model.triangles(0, t)), x.col(model.triangles(1, t)), x.col(model.triangles(2, t)),
                        model.membrane.rest[t], model.membrane.material, &tg, &th, true);
        g += tg.segment<3>(3 * k);
        hess += th.block<3, 3>(3 * k, 3 * k);
      }
      for (const auto& [e, k] : inc.hinges[i]) {
        const auto hv = model.bending.hinges.col(e);
        const HingeGaussNewton gn = hinge_bending_gauss_newton(x.col(hv[0]), x.col(hv[1]), x.col(hv[2]),
                                                               x.col(hv[3]), model.bending.rest[e],
                                                               model.bending.stiffness);
        g += gn.gradient.segment<3>(3 * k);
        const Vec3 a = gn.angle_gradient.segment<3>(3 * k);
        hess += gn.curvature * a * a.transpose();
      }
      const Eigen::LDLT<Mat3> solve(hess);
      if (solve.info() == Eigen::Success) x.col(i) -= solve.solve(g);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  int resolution = 64, frames = 20, sweeps = 200;
  bool polish = false;
  double rho = 0.0;
  for (int a = 1; a < argc; ++a) {
    const bool value = a + 1 < argc;
    if (std::strcmp(argv[a], "--resolution") == 0 && value) {
      resolution = std::stoi(argv[++a]);
    } else if (std::strcmp(argv[a], "--frames") == 0 && value) {
      frames = std::stoi(argv[++a]);
    } else if (std::strcmp(argv[a], "--sweeps") == 0 && value) {
      sweeps = std::stoi(argv[++a]);
    } else if (std::strcmp(argv[a], "--polish") == 0) {
      polish = true;
    } else if (std::strcmp(argv[a], "--rho") == 0 && value) {
      rho = std::stod(argv[++a]);
    } else {
      std::fprintf(stderr, "usage: %s [--resolution 64] [--frames 20] [--sweeps 200] [--rho 0] [--polish]\n",
                   argv[0]);
      return 2;
    }
  }
  const std::string grid = "cloths.0.grid.resolution=[" + std::to_string(resolution) + "," + std::to_string(resolution) + "]";
  const SceneDesc scene = load_scene_file(std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json", {grid});
  World world = build_world(scene);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  for (int s = 0; s < frames * schedule.steps_per_frame; ++s) world.step();
  const Cloth start = world.cloths()[0];
  const ClothModel& model = start.model;
  const Vec3 gravity = world.settings.gravity;
  const double h = world.settings.time_step;
  const Positions x_start = start.state.x;
  const Positions x_hat = x_start + h * start.state.v;
  Positions gradient;
  std::printf("method,iteration,seconds,residual\n");
  std::printf("start,0,0,%.3e\n", residual_at(model, gravity, x_hat, x_start, x_hat, h, gradient));

  // Newton + CG capped at k iterations; each k from a fresh copy, its own time.
  for (int k = 1; k <= 12; ++k) {
    Cloth cloth = start;
    ImplicitEulerSolver solver;
    ImplicitEulerSettings settings = world.settings.implicit;
    settings.max_newton_iterations = k;
    settings.newton_tolerance = 1e-12;
    solver.step(cloth, gravity, h, settings);  // warms the solver's storage
    cloth = start;
    const auto begin = Clock::now();
    solver.step(cloth, gravity, h, settings);
    const double seconds = seconds_since(begin);
    std::printf("newton,%d,%.4f,%.3e\n", k, seconds,
                residual_at(model, gravity, cloth.state.x, x_start, x_hat, h, gradient));
  }

  const std::vector<std::vector<int>> colours = colour_vertices(model);
  const Incidence inc = incidence(model);
  if (polish) {
    // Newton capped at k, then Gauss-Seidel sweeps over only the vertices whose residual is above
    // the scene's tolerance and their neighbours: does the tail of a step's residual sit where
    // local updates can finish it?
    const std::vector<std::vector<int>> neighbours = vertex_neighbours(model);
    const double tolerance = world.settings.implicit.newton_tolerance;
    for (int k = 3; k <= 8; ++k) {
      Positions xp = newton_capped(start, world, k).state.x;
      double residual = residual_at(model, gravity, xp, x_start, x_hat, h, gradient);
      for (int sweep = 0; sweep <= 30; ++sweep) {
        std::vector<char> active(model.mass.size(), 0);
        int above = 0, touched = 0;
        for (Eigen::Index i = 0; i < xp.cols(); ++i) {
          if (h * gradient.col(i).norm() * model.inverse_mass[i] <= tolerance) continue;
          ++above;
          active[i] = 1;
          for (const int w : neighbours[i]) active[w] = 1;
        }
        for (const char a : active) touched += a;
        std::printf("polish_after_newton_%d,%d,%d above,%d touched,%.3e\n", k, sweep, above, touched,
                    residual);
        if (above == 0) break;
        vbd_sweep(model, gravity, h, x_start, x_hat, colours, inc, xp, &active);
        residual = residual_at(model, gravity, xp, x_start, x_hat, h, gradient);
      }
    }
    // The same tail by restricted Newton iterations: the projected Hessian of the whole cloth at
    // the iterate, its rows and columns of the vertices above the tolerance and their neighbours
    // solved exactly (the rest held), the full step taken.
    SparseHessian hessian;
    HessianStencils stencils;
    prepare_hessian(model, hessian, stencils);
    for (int k = 3; k <= 16; ++k) {
      const bool frozen = k > 8;  // k - 5: the Hessian kept from the first restricted iteration
      Positions xp = newton_capped(start, world, frozen ? k - 5 : k).state.x;
      double residual = residual_at(model, gravity, xp, x_start, x_hat, h, gradient);
      for (int iteration = 0; iteration <= 8; ++iteration) {
        std::vector<int> local(model.mass.size(), -1);
        std::vector<int> region;
        int above = 0;
        for (Eigen::Index i = 0; i < xp.cols(); ++i) {
          if (h * gradient.col(i).norm() * model.inverse_mass[i] <= tolerance) continue;
          ++above;
          for (const int w : neighbours[i]) {
            if (local[w] < 0 && model.inverse_mass[w] > 0.0) {
              local[w] = static_cast<int>(region.size());
              region.push_back(w);
            }
          }
          if (local[i] < 0) {
            local[i] = static_cast<int>(region.size());
            region.push_back(static_cast<int>(i));
          }
        }
        std::printf("%s_after_newton_%d,%d,%d above,%zu touched,%.3e\n", frozen ? "frozen" : "restricted",
                    frozen ? k - 5 : k, iteration, above, region.size(), residual);
        if (above == 0) break;
        if (!frozen || iteration == 0) {
          hessian.set_zero();
          evaluate_mass_quadratic(model.mass, 1.0 / (h * h), xp, x_hat, nullptr, &hessian);
          evaluate_potential(model, gravity, xp, nullptr, &hessian, stencils, true);
          evaluate_dissipation(model, x_start, xp, h, nullptr, &hessian, stencils);
          hessian.finish_assembly();
        }
        const SparseHessian::Matrix& full = hessian.matrix();
        std::vector<Eigen::Triplet<double>> entries;
        Eigen::VectorXd rhs(3 * region.size());
        for (size_t a = 0; a < region.size(); ++a) {
          for (int r = 0; r < 3; ++r) {
            const int row = 3 * region[a] + r;
            rhs[3 * a + r] = -gradient(r, region[a]);
            for (SparseHessian::Matrix::InnerIterator it(full, row); it; ++it) {
              const int b = local[it.col() / 3];
              if (b >= 0) entries.emplace_back(3 * a + r, 3 * b + it.col() % 3, it.value());
            }
          }
        }
        Eigen::SparseMatrix<double> restricted(rhs.size(), rhs.size());
        restricted.setFromTriplets(entries.begin(), entries.end());
        const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solve(restricted);
        const Eigen::VectorXd dx = solve.solve(rhs);
        for (size_t a = 0; a < region.size(); ++a) xp.col(region[a]) += dx.segment<3>(3 * a);
        residual = residual_at(model, gravity, xp, x_start, x_hat, h, gradient);
      }
    }
    return 0;
  }

  // VBD from the inertial predictor.
  std::fprintf(stderr, "%zu vertex colours\n", colours.size());
  Positions x = x_hat, previous = x_hat, before_previous = x_hat;
  double omega = 1.0, seconds = 0.0;
  for (int k = 1; k <= sweeps; ++k) {
    const auto begin = Clock::now();
    vbd_sweep(model, gravity, h, x_start, x_hat, colours, inc, x);
    if (rho > 0.0) {
      // Chebyshev semi-iteration (Wang 2015): x_k = omega (x_k - x_{k-2}) + x_{k-2}.
      omega = k == 1 ? 1.0 : k == 2 ? 2.0 / (2.0 - rho * rho) : 4.0 / (4.0 - rho * rho * omega);
      if (k > 1) x = omega * (x - before_previous) + before_previous;
      before_previous = previous;
      previous = x;
    }
    seconds += seconds_since(begin);
    if (k <= 10 || k % 10 == 0) {
      std::printf("vbd,%d,%.4f,%.3e\n", k, seconds, residual_at(model, gravity, x, x_start, x_hat, h, gradient));
    }
  }
  return 0;
}
