#include "app/headless_runner.hpp"

#include <omp.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "app/progress.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/obj_io.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "weft/version.hpp"

namespace weft {

namespace {

volatile std::sig_atomic_t stop_requested = 0;
extern "C" void request_stop(int) { stop_requested = 1; }

// Ctrl-C and SIGTERM (a cluster's time limit) finish the frame in progress and stop.
void install_stop_handlers() {
  stop_requested = 0;
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

std::string frame_file_name(int frame, int total_frames) {
  const int digits = std::max(4, static_cast<int>(std::to_string(total_frames).size()));
  std::ostringstream name;
  name << "frame_" << std::setw(digits) << std::setfill('0') << frame << ".obj";
  return name.str();
}

void write_frame(const World& world, const std::filesystem::path& path) {
  std::vector<ObjObject> objects;
  for (const Cloth& cloth : world.cloths()) {
    objects.push_back({cloth.model.name, &cloth.state.x, &cloth.model.triangles, &cloth.model.uvs, true});
  }
  write_file_atomically(path.string(), [&](std::ostream& out) { write_obj(out, objects); });
}

// The first vertex with a non-finite position or velocity, as a message; empty if all are finite.
std::string find_non_finite(const World& world) {
  for (const Cloth& cloth : world.cloths()) {
    for (int i = 0; i < cloth.num_vertices(); ++i) {
      const bool position_bad = !cloth.state.x.col(i).allFinite();
      if (position_bad || !cloth.state.v.col(i).allFinite()) {
        return "cloth \"" + cloth.model.name + "\" vertex " + std::to_string(i) + " has a non-finite " +
               (position_bad ? "position" : "velocity");
      }
    }
  }
  return {};
}

struct FrameStats {
  int frame = 0;
  double time = 0.0;
  Energies energies;
  double dissipated = 0.0;  // J: total energy lost since frame 0 (damping, contact, friction)
  StepStats steps;          // summed over the frame's steps
  double wall_ms = 0.0;
};

void write_stats(const std::filesystem::path& path, const std::vector<FrameStats>& rows) {
  write_file_atomically(path.string(), [&](std::ostream& out) {
    out << "frame,time,kinetic_energy,potential_energy,gravitational_energy,elastic_energy,spring_energy,"
           "energy_dissipated,contacts,newton_iterations,linear_iterations,accepted_steps,rejected_steps,"
           "integrate_ms,collisions_ms,wall_ms,steps,broad_phase_ms,narrow_phase_ms,response_ms,step_ms,"
           "vertex_face_candidates,edge_edge_candidates,proximity_contacts,ccd_impulses,impact_zone_vertices,"
           "collisions_clean\n";
    out << std::setprecision(10);
    for (const FrameStats& row : rows) {
      const Energies& e = row.energies;
      const StepStats& s = row.steps;
      out << row.frame << ',' << row.time << ',' << e.kinetic << ',' << e.gravitational + e.elastic << ','
          << e.gravitational << ',' << e.elastic << ',' << e.terms.springs << ',' << row.dissipated << ','
          << s.contacts << ',' << s.newton_iterations << ',' << s.linear_iterations << ',' << s.accepted_steps
          << ',' << s.rejected_steps << ',' << s.integrate_ms << ',' << s.collisions_ms << ',' << row.wall_ms
          << ',' << s.steps << ',' << s.broad_phase_ms << ',' << s.narrow_phase_ms << ',' << s.response_ms << ','
          << s.total_ms << ',' << s.vertex_face_candidates << ',' << s.edge_edge_candidates << ','
          << s.proximity_contacts << ',' << s.ccd_impulses << ',' << s.impact_zone_vertices << ','
          << (s.collisions_clean ? 1 : 0) << '\n';
    }
  });
}

void write_run_json(const std::filesystem::path& path, const HeadlessOptions& options, const SceneDesc& scene,
                    const std::string& status, int frames_written) {
  nlohmann::json run = {{"weft_version", version_string},
                        {"git_commit", git_commit},
                        {"scene_file", options.scene_path},
                        {"overrides", options.overrides},
                        {"status", status},
                        {"frames_written", frames_written},
                        {"scene", scene_to_json(scene)}};
  write_file_atomically(path.string(), [&](std::ostream& out) { out << run.dump(2) << '\n'; });
}

}  // namespace

int run_headless(const HeadlessOptions& options) {
  // Read and check everything before touching the output folder.
  std::vector<std::string> overrides = options.overrides;
  if (options.frames >= 0) overrides.push_back("frames=" + std::to_string(options.frames));
  SceneDesc scene;
  World world;
  try {
    scene = load_scene_file(options.scene_path, overrides);
    world = build_world(scene);
    world.settings.threads = options.threads > 0 ? options.threads : omp_get_num_procs();
  } catch (const SceneError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 2;
  }

  const std::filesystem::path out_dir(options.out_dir);
  const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
  HeadlessOptions recorded = options;
  recorded.overrides = overrides;
  std::vector<FrameStats> rows;
  int frames_written = 0;
  try {
    std::error_code error;
    std::filesystem::create_directories(out_dir, error);
    if (error || !std::filesystem::is_directory(out_dir)) {
      throw IoError(options.out_dir + ": cannot create output folder" + (error ? ": " + error.message() : ""));
    }
    write_run_json(out_dir / "run.json", recorded, scene, "running", 0);

    install_stop_handlers();
    ProgressReporter progress(scene.frames, !options.quiet);
    const double initial_energy = world.energies().total();
    const auto record = [&](int frame, const StepStats& steps, double wall_ms) {
      write_frame(world, out_dir / frame_file_name(frame, scene.frames));
      const Energies energies = world.energies();
      rows.push_back({frame, world.time(), energies, initial_energy - energies.total(), steps, wall_ms});
      write_stats(out_dir / "stats.csv", rows);
      frames_written = frame + 1;
    };

    record(0, StepStats{}, 0.0);
    for (int frame = 1; frame <= scene.frames; ++frame) {
      if (stop_requested) break;
      const auto start = std::chrono::steady_clock::now();
      StepStats frame_steps;
      for (int step = 0; step < schedule.steps_per_frame; ++step) {
        world.step();
        frame_steps += world.last_step_stats();
      }
      const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      if (const std::string bad = find_non_finite(world); !bad.empty()) {
        progress.finish(frame - 1);
        std::fprintf(stderr,
                     "weft: the simulation diverged in frame %d (t = %.6g s): %s. Frames 0..%d are written. "
                     "Try a smaller solver.time_step, more solver.substeps or softer springs.\n",
                     frame, world.time(), bad.c_str(), frame - 1);
        write_run_json(out_dir / "run.json", recorded, scene, "diverged", frames_written);
        return 3;
      }
      record(frame, frame_steps, wall_ms);
      progress.update(frame);
    }
    progress.finish(frames_written - 1);
    if (stop_requested) {
      write_run_json(out_dir / "run.json", recorded, scene, "interrupted", frames_written);
      std::fprintf(stderr, "weft: interrupted; frames 0..%d in %s are complete\n", frames_written - 1,
                   options.out_dir.c_str());
      return 130;
    }
    write_run_json(out_dir / "run.json", recorded, scene, "complete", frames_written);
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 4;
  }
  return 0;
}

}  // namespace weft
