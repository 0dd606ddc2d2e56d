// Runs a scene to its end and checks the collision invariants after every frame with the checker
// the tests use (tests/support/scene_invariants.hpp: exact triangle intersections, vertices
// crossing analytic solids), printing one CSV line per frame. Exit code 0: every frame clean;
// 1: a violation (the run stops there); 2: bad input.
//   weft_check_scene scenes/twist.json [--set path=value ...] [--frames N] [--threads N]
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "support/scene_invariants.hpp"

int main(int argc, char** argv) {
  using namespace weft;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s scene.json [--set path=value ...] [--frames N] [--threads N]\n", argv[0]);
    return 2;
  }
  std::vector<std::string> overrides;
  int frames = -1;
  int threads = 1;
  for (int k = 2; k < argc; ++k) {
    const bool has_value = k + 1 < argc;
    if (std::strcmp(argv[k], "--set") == 0 && has_value) {
      overrides.push_back(argv[++k]);
    } else if (std::strcmp(argv[k], "--frames") == 0 && has_value) {
      frames = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--threads") == 0 && has_value) {
      threads = std::atoi(argv[++k]);
    } else {
      std::fprintf(stderr, "unknown or incomplete argument: %s\n", argv[k]);
      return 2;
    }
  }
  try {
    const SceneDesc scene = load_scene_file(argv[1], overrides);
    World world = build_world(scene);
    world.settings.threads = std::max(1, threads);
    if (frames < 0) frames = scene.frames;
    const testing::SceneInvariants invariants(world);
    const FrameSchedule schedule = frame_schedule(scene.fps, scene.time_step);
    std::printf("frame,time,steps,contacts,intersecting_pairs,vertices_crossed,step_ms,collision_ms,broad_ms,"
                "narrow_ms,response_ms,newton_iterations,linear_iterations\n");
    testing::InvariantReport report = invariants.check(world);
    for (int frame = 0; frame <= frames; ++frame) {
      StepStats totals;
      if (frame > 0) {
        for (int step = 0; step < schedule.steps_per_frame; ++step) {
          world.step();
          totals += world.last_step_stats();
        }
        report = invariants.check(world);
      }
      std::printf("%d,%.6f,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d\n", frame, world.time(), totals.steps,
                  totals.contacts, report.intersecting_pairs, report.vertices_crossed, totals.total_ms,
                  totals.collisions_ms, totals.broad_phase_ms, totals.narrow_phase_ms, totals.response_ms,
                  totals.newton_iterations, totals.linear_iterations);
      std::fflush(stdout);
      if (!report.ok()) {
        std::fprintf(stderr, "%s: frame %d: %s\n", argv[1], frame, report.first.c_str());
        return 1;
      }
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }
  return 0;
}
