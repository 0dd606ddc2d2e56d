// The speed/accuracy trade, measured: every integrator at every step size h on one scene, each
// compared with a fine-step reference (midpoint at a step far below the explicit limit).
//
//   cmake --build build/release --target weft_tradeoff
//   build/release/bench/weft_tradeoff scenes/swing.json --duration 0.5 --out out/tradeoff
//
// Writes OUT/tradeoff.csv (integrator, h, wall seconds per simulated second, largest position
// error against the reference at the end, energy drift, largest strain, stable) and
// OUT/pareto.png (gnuplot: error against cost, one series per integrator). The scene should have
// no contact (collisions are switched off here): the errors are those of the time integration.
// XPBD runs one sweep per step of h (substeps 1), so its h is its sub-step.
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/gnuplot_quote.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"
#include "sim/world.hpp"

namespace {

using namespace weft;
namespace fs = std::filesystem;

struct Run {
  Positions x;            // every cloth's positions at the end, side by side
  double energy_end = 0.0, peak_kinetic = 0.0;
  double wall_seconds = 0.0;
  double largest_strain = 0.0;
  bool stable = true;
};

Positions all_positions(const World& world) {
  Eigen::Index n = 0;
  for (const Cloth& cloth : world.cloths()) n += cloth.num_vertices();
  Positions x(3, n);
  n = 0;
  for (const Cloth& cloth : world.cloths()) {
    x.middleCols(n, cloth.num_vertices()) = cloth.state.x;
    n += cloth.num_vertices();
  }
  return x;
}

// Runs `scene` for `duration` with the given integrator and step; strain, energy and stability
// are sampled every `sample` seconds. A run stops early (unstable) on non-finite state, a strain
// past 1 (twice the rest length) or a total energy above its start by more than `energy_gain`
// (J): a run that creates energy has blown up however little it has stretched yet.
Run simulate(SceneDesc scene, IntegratorKind integrator, double h, double duration, double sample,
             double energy_gain = INFINITY) {
  scene.integrator = integrator;
  scene.collision.enabled = false;
  scene.xpbd = XpbdSettings{1, 1};
  World world = build_world(scene);
  world.settings.time_step = h;
  world.settings.threads = 1;
  const int steps = static_cast<int>(std::lround(duration / h));
  const int sample_every = std::max(1, static_cast<int>(std::lround(sample / h)));
  Run run;
  const double energy_start = world.energies().total();
  double seconds = 0.0;
  for (int k = 1; k <= steps && run.stable; ++k) {
    const auto start = std::chrono::steady_clock::now();
    world.step();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (k % sample_every == 0 || k == steps) {
      const Energies energies = world.energies();
      run.peak_kinetic = std::max(run.peak_kinetic, energies.kinetic);
      bool finite = std::isfinite(energies.total());
      for (const Cloth& cloth : world.cloths()) finite = finite && cloth.state.x.allFinite() && cloth.state.v.allFinite();
      run.largest_strain = finite ? std::max(run.largest_strain, largest_strain(world)) : INFINITY;
      run.stable = finite && run.largest_strain <= 1.0 && energies.total() - energy_start <= energy_gain;
      run.energy_end = energies.total();
    }
  }
  run.wall_seconds = seconds;
  run.x = all_positions(world);
  return run;
}

int usage() {
  std::fprintf(stderr,
               "usage: weft_tradeoff SCENE [--out DIR] [--duration S] [--set PATH=VALUE]...\n"
               "  sweeps symplectic_euler, midpoint_euler_cromer, explicit_midpoint, implicit_euler and xpbd over\n"
               "  h = 1/16000 ... 1/24 s, then bisects the explicit integrators' largest stable step\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  std::string out = "out/tradeoff";
  double duration = 1.0;
  std::vector<std::string> overrides;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (arg == "--duration" && i + 1 < argc) {
      duration = std::atof(argv[++i]);
      if (!(duration > 0.0)) {
        std::fprintf(stderr, "weft_tradeoff: --duration: expected a number of seconds > 0, got %s\n", argv[i]);
        return 2;
      }
    } else if (arg == "--set" && i + 1 < argc) {
      overrides.push_back(argv[++i]);
    } else {
      return usage();
    }
  }
  try {
    omp_set_num_threads(1);
    const SceneDesc scene = load_scene_file(argv[1], overrides);
    const double sample = 1.0 / 120.0;
    const double reference_h = 1.0 / 128000.0;
    std::printf("reference: midpoint at h = 1/%.0f s over %.3g s\n", 1.0 / reference_h, duration);
    const Run reference = simulate(scene, IntegratorKind::explicit_midpoint, reference_h, duration, sample);
    if (!reference.stable) {
      std::fprintf(stderr, "weft_tradeoff: %s: the reference run (midpoint, h = %.3g s) is unstable\n", argv[1],
                   reference_h);
      return 1;
    }
    fs::create_directories(out);
    const std::string csv_path = (fs::path(out) / "tradeoff.csv").string();
    std::ofstream csv(csv_path + ".tmp");
    csv << "integrator,h,wall_s_per_sim_s,position_error_m,energy_drift,largest_strain,stable\n";
    const std::vector<double> steps = {1.0 / 16000, 1.0 / 8000, 1.0 / 4000, 1.0 / 2000, 1.0 / 1000,
                                       1.0 / 480,   1.0 / 240,  1.0 / 120,  1.0 / 60,   1.0 / 24};
    for (IntegratorKind integrator : {IntegratorKind::symplectic_euler, IntegratorKind::midpoint_euler_cromer,
                                      IntegratorKind::explicit_midpoint, IntegratorKind::implicit_euler,
                                      IntegratorKind::xpbd}) {
      // Stable: finite, no side past 2x, and no more energy gained than a tenth of the
      // reference's peak kinetic energy. XPBD is exempt from the energy test: its membrane is
      // edge constraints, not the scene's StVK model the energy is measured in, so it shows
      // energy "gained" at every h while bounded (its drift column says how much).
      const double energy_gain = integrator == IntegratorKind::xpbd ? INFINITY : 0.1 * reference.peak_kinetic;
      double largest_stable = 0.0, smallest_unstable = INFINITY;
      for (double h : steps) {
        const Run run = simulate(scene, integrator, h, duration, sample, energy_gain);
        if (run.stable) largest_stable = std::max(largest_stable, h);
        if (!run.stable) smallest_unstable = std::min(smallest_unstable, h);
        const double error = run.stable ? (run.x - reference.x).colwise().norm().maxCoeff() : NAN;
        // Energy gained (+) or lost (-) against the reference's, over the reference's peak kinetic energy.
        const double drift = run.stable ? (run.energy_end - reference.energy_end) / reference.peak_kinetic : NAN;
        char line[256];
        std::snprintf(line, sizeof line, "%s,%.8g,%.6g,%.6g,%.6g,%.6g,%s", to_string(integrator), h,
                      run.stable ? run.wall_seconds / duration : NAN, error, drift, run.largest_strain,
                      run.stable ? "yes" : "no");
        csv << line << "\n";
        std::printf("%s\n", line);
        std::fflush(stdout);
      }
      // The explicit integrators' limit on this scene: bisected between the sweep's largest stable
      // and smallest unstable step, to 1% (stable means the same as above).
      const bool explicit_integrator = integrator == IntegratorKind::symplectic_euler ||
                                       integrator == IntegratorKind::midpoint_euler_cromer ||
                                       integrator == IntegratorKind::explicit_midpoint;
      if (explicit_integrator && largest_stable > 0.0 && std::isfinite(smallest_unstable) &&
          largest_stable < smallest_unstable) {
        double lo = largest_stable, hi = smallest_unstable;
        while (hi - lo > 0.01 * lo) {
          const double mid = std::sqrt(lo * hi);
          (simulate(scene, integrator, mid, duration, sample, energy_gain).stable ? lo : hi) = mid;
        }
        std::printf("limit,%s,largest stable h = 1/%.0f s (unstable at 1/%.0f s)\n", to_string(integrator), 1.0 / lo,
                    1.0 / hi);
        std::fflush(stdout);
      }
    }
    csv.close();
    fs::rename(csv_path + ".tmp", csv_path);

    const std::string png = (fs::path(out) / "pareto.png").string();
    const std::string script = (fs::path(out) / "pareto.gp").string();
    std::ofstream gp(script);
    gp << "set terminal pngcairo size 900,600 noenhanced\n"
       << "set output " << gnuplot_quote(png) << "\n"
       << "set datafile separator ','\n"
       << "set logscale xy\n"
       << "set grid\n"
       << "set title " << gnuplot_quote("speed/accuracy on " + scene.name + " (stable runs; labels: 1/h)") << "\n"
       << "set xlabel 'wall seconds per simulated second (1 thread)'\n"
       << "set ylabel 'largest position error at t = " << duration << " s (m)'\n"
       << "set key top right\n"
       << "plot ";
    const char* names[] = {"symplectic_euler", "midpoint_euler_cromer", "explicit_midpoint", "implicit_euler", "xpbd"};
    for (int k = 0; k < 5; ++k) {
      const std::string filter = "(strcol(1) eq '" + std::string(names[k]) + "' && strcol(7) eq 'yes' ? ";
      gp << (k ? ", \\\n     " : "") << gnuplot_quote(csv_path) << " every ::1 using " << filter << "$3 : NaN):4 with linespoints pt "
         << (k + 5) << " title '" << names[k] << "', \\\n     " << gnuplot_quote(csv_path) << " every ::1 using " << filter
         << "$3 : NaN):4:(sprintf('%.0f', 1/$2)) with labels offset 0.8,0.6 font ',7' notitle";
    }
    gp << "\n";
    gp.close();
    const std::string command = "gnuplot " + script;
    if (std::system(command.c_str()) != 0) {
      std::fprintf(stderr, "weft_tradeoff: gnuplot failed on %s (install gnuplot-nox)\n", script.c_str());
      return 4;
    }
    std::printf("wrote %s and %s\n", csv_path.c_str(), png.c_str());
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }
}
