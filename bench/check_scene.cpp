// Runs a scene to its end and checks the collision invariants after every frame with the checker
// the tests use (tests/support/scene_invariants.hpp: exact triangle intersections, vertices
// crossing analytic solids) and the headless runner's divergence bounds (sim/stability.hpp:
// speed 100 m/s, stretch 6x), printing one CSV line per frame; `largest_strain` is the largest
// stretch - 1 of any spring or membrane triangle, `largest_edge_stretch` the largest triangle side
// over its rest length (checked against collision.strain_limit where the scene sets one). Exit
// code 0: every frame clean;
// 1: a violation (the run stops there); 2: bad input.
//   weft_check_scene scenes/twist.json [--set path=value ...] [--frames N] [--threads N]
//                    [--resume DIR/checkpoint.bin] [--every-step] [--keep-going]
// --resume starts from a headless run's checkpoint (`weft --headless --checkpoint-every N`);
// --every-step checks after every step instead of every frame (one line per step), to find the
// step where a violation first appears; --keep-going runs on past invariant violations (each
// named on stderr, the exit code 1 at the end) to see how a run fares after its first one
// (divergence still stops it).
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"
#include "support/scene_invariants.hpp"

int main(int argc, char** argv) {
  using namespace weft;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s scene.json [--set path=value ...] [--frames N] [--threads N] [--resume FILE] [--every-step] [--keep-going]\n", argv[0]);
    return 2;
  }
  std::vector<std::string> overrides;
  int frames = -1;
  int threads = 1;
  std::string resume;
  bool every_step = false;
  bool keep_going = false;
  for (int k = 2; k < argc; ++k) {
    const bool has_value = k + 1 < argc;
    if (std::strcmp(argv[k], "--set") == 0 && has_value) {
      overrides.push_back(argv[++k]);
    } else if (std::strcmp(argv[k], "--frames") == 0 && has_value) {
      frames = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--threads") == 0 && has_value) {
      threads = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--resume") == 0 && has_value) {
      resume = argv[++k];
    } else if (std::strcmp(argv[k], "--every-step") == 0) {
      every_step = true;
    } else if (std::strcmp(argv[k], "--keep-going") == 0) {
      keep_going = true;
    } else {
      std::fprintf(stderr, "unknown or incomplete argument: %s\n", argv[k]);
      return 2;
    }
  }
  try {
    const SceneDesc scene = load_scene_file(argv[1], overrides);
    World world = build_world(scene);
    world.settings.threads = std::max(1, threads);
    int first_frame = 0;
    if (!resume.empty()) {
      const Checkpoint checkpoint = read_checkpoint(resume);
      restore_checkpoint(checkpoint, world, resume);
      first_frame = checkpoint.frame;
    }
    if (frames < 0) frames = scene.frames;
    const testing::SceneInvariants invariants(world);
    const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
    int violations = 0;
    std::printf("frame,step,time,steps,contacts,intersecting_pairs,vertices_crossed,step_ms,collision_ms,broad_ms,"
                "narrow_ms,response_ms,newton_iterations,linear_iterations,impact_zone_vertices,collisions_clean,largest_strain,"
                "largest_edge_stretch\n");
    const auto print = [&](int frame, int step, const StepStats& totals,
                           const testing::InvariantReport& report) {
      std::printf("%d,%d,%.6f,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d,%d,%d,%.3f,%.4f\n", frame, step,
                  world.time(), totals.steps, totals.contacts, report.intersecting_pairs,
                  report.vertices_crossed, totals.total_ms, totals.collisions_ms, totals.collision.broad_ms,
                  totals.collision.narrow_ms, totals.collision.response_ms, totals.newton_iterations,
                  totals.linear_iterations, totals.collision.impact_zone_vertices,
                  totals.collision.clean ? 1 : 0, largest_strain(world), report.largest_edge_stretch);
      std::fflush(stdout);
      Instability unstable = check_state(world, StabilityLimits{});
      if (!unstable.found) unstable = check_strain(world, StabilityLimits{});
      if (unstable.found) {
        std::fprintf(stderr, "%s: frame %d step %d: %s\n", argv[1], frame, step, unstable.describe().c_str());
        return false;
      }
      if (report.ok()) return true;
      std::fprintf(stderr, "%s: frame %d step %d: %s\n", argv[1], frame, step, report.first.c_str());
      ++violations;
      return keep_going;
    };
    testing::InvariantReport report = invariants.check(world);
    if (!print(first_frame, 0, StepStats{}, report)) return 1;
    for (int frame = first_frame + 1; frame <= frames; ++frame) {
      StepStats totals;
      for (int step = 1; step <= schedule.steps_per_frame; ++step) {
        world.step();
        totals += world.last_step_stats();
        if (every_step) {
          report = invariants.check(world);
          if (!print(frame, step, world.last_step_stats(), report)) return 1;
        }
      }
      if (!every_step) {
        report = invariants.check(world);
        if (!print(frame, schedule.steps_per_frame, totals, report)) return 1;
      }
    }
    return violations > 0 ? 1 : 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }
}
