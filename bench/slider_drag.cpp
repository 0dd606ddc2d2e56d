// The simulation half of "the 32x32 drape plays in real time in the viewer while a stiffness
// slider is dragged" (docs/performance.md, "Targets"): the drape's fast tier stepped frame by
// frame as the viewer steps it, with the material panel's edit (ui/material_edit.hpp:
// read_material, apply_material on World::cloths()) applied before every frame, as a slider
// dragged through its range does. Prints wall seconds per simulated second of the frames (edits
// included; no rendering) for an undisturbed run and for each slider, one line each. Timings only:
// nothing here is pass/fail.
//   cmake --build build/release --target weft_slider_drag
//   build/release/bench/weft_slider_drag [--threads T] [--resolution N] [--set path=value ...]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/world.hpp"
#include "ui/material_edit.hpp"

namespace {

using weft::ClothMaterial;

// One slider: the value it sets at drag position s in [0, 1] (a log slider sweeps its range).
struct Drag {
  const char* name;
  std::function<void(ClothMaterial&, const ClothMaterial&, double)> set;
};

// Drag position at frame f: back and forth over the range once every 30 frames (a second).
double position(int frame) { return 0.5 - 0.5 * std::cos(2.0 * M_PI * frame / 30.0); }

double log_between(double low, double high, double s) { return low * std::pow(high / low, s); }

struct Run {
  double wall_per_simulated = 0.0;  // s per simulated s, edits included
  double edit_seconds = 0.0;        // of it, the edits themselves
  int unconverged = 0;
  bool clean = true;
  double mean_height = 0.0;  // of the cloth at the end: tells that the edits took effect
};

Run run(const weft::SceneDesc& scene, int threads, const Drag* drag) {
  weft::World world = weft::build_world(scene);
  world.settings.threads = threads;
  // The frame cut as build_world cut it into world.settings.time_step.
  const weft::FrameSchedule schedule = weft::frame_schedule(scene.fps, scene.time_step);
  const ClothMaterial shipped = weft::read_material(world.cloths()[0].model);
  Run result;
  double seconds = 0.0;
  for (int frame = 1; frame <= scene.frames; ++frame) {
    const auto start = std::chrono::steady_clock::now();
    if (drag != nullptr) {
      const auto edit_start = std::chrono::steady_clock::now();
      weft::ClothModel& model = world.cloths()[0].model;  // as the material panel edits it
      ClothMaterial material = weft::read_material(model);
      drag->set(material, shipped, position(frame));
      weft::apply_material(model, material);
      result.edit_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - edit_start).count();
    }
    for (int k = 0; k < schedule.steps_per_frame; ++k) {
      world.step();
      result.unconverged += world.last_step_stats().unconverged_steps;
      result.clean = result.clean && world.last_step_stats().collision.clean;
    }
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  result.wall_per_simulated = seconds / (scene.frames / scene.fps);
  result.mean_height = world.cloths()[0].state.x.row(1).mean();
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 1;
  int resolution = 32;
  std::vector<std::string> overrides;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--threads") == 0 && k + 1 < argc) {
      threads = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--resolution") == 0 && k + 1 < argc) {
      resolution = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--set") == 0 && k + 1 < argc) {
      overrides.push_back(argv[++k]);
    } else {
      std::fprintf(stderr, "usage: %s [--threads T] [--resolution N] [--set path=value ...]\n", argv[0]);
      return 2;
    }
  }
  if (threads < 1 || resolution < 2) {
    std::fprintf(stderr, "weft_slider_drag: --threads must be >= 1 and --resolution >= 2\n");
    return 2;
  }
  overrides.insert(overrides.begin(), "cloths.0.grid.resolution=[" + std::to_string(resolution) + "," +
                                          std::to_string(resolution) + "]");
  try {
    const weft::SceneDesc scene =
        weft::load_scene_file(std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere_fast.json", overrides);
    // The material panel's stiffness sliders and the density one, each over a decade or two
    // around the shipped value (the panel's own ranges are wider).
    const std::vector<Drag> drags = {
        {"membrane Young's modulus",
         [](ClothMaterial& m, const ClothMaterial& s, double p) {
           m.membrane.young_modulus = log_between(0.1, 10.0, p) * s.membrane.young_modulus;
         }},
        {"bending stiffness",
         [](ClothMaterial& m, const ClothMaterial& s, double p) {
           m.bending_stiffness = log_between(0.01, 100.0, p) * s.bending_stiffness;
         }},
        {"density", [](ClothMaterial& m, const ClothMaterial& s,
                       double p) { m.area_density = log_between(0.5, 2.0, p) * s.area_density; }},
    };
    std::printf("drape_sphere_fast at %dx%d, %d frames at %.0f fps, %d thread(s); wall s per simulated s\n",
                resolution, resolution, scene.frames, scene.fps, threads);
    const auto line = [](const char* name, const Run& r) {
      std::printf("%-28s %7.3f s  (edits %.4f s; final mean height %.4f m; unconverged steps %d; %s)\n", name,
                  r.wall_per_simulated, r.edit_seconds, r.mean_height, r.unconverged,
                  r.clean ? "every step clean" : "SOME STEP UNCLEAN");
    };
    line("no slider", run(scene, threads, nullptr));
    for (const Drag& drag : drags) line(drag.name, run(scene, threads, &drag));
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "weft_slider_drag: %s\n", error.what());
    return 2;
  }
}
