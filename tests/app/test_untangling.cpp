// Untangling (collision.untangle, on by default) through the weft program: each scene in
// tests/data starts tangled (said on stderr), and from the first recorded frame on the exact check
// (stats.csv, written apart from the untangling) finds no intersecting pair and no vertex inside a
// collider. With untangling off the same scenes stay tangled. A vertex pinned inside a collider,
// which untangling cannot move, is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;

struct TangledScene {
  const char* file;  // in tests/data
  int frames;
};

// Frames per scene: long enough that a cloth falls onto what is under it and settles there.
const TangledScene tangled_scenes[] = {
    {"tangled_sheets.json", 12},   // two sheets on a table, one laid through the other
    {"sheet_in_sphere.json", 12},  // a sheet whose middle starts 3.9 cm inside a sphere
    {"folded_through.json", 12},   // a sheet folded over, its flap through the sheet
    {"pinched_tube.json", 12},     // an OBJ tube whose top wall is pinched through its bottom wall
};

struct Counts {
  std::vector<double> pairs;
  std::vector<double> inside;
};

Counts run_scene(const TangledScene& scene, const TempDir& dir, const std::vector<std::string>& more,
                 ProgramResult* result_out = nullptr) {
  const fs::path out = dir.path() / fs::path(scene.file).stem();
  std::vector<std::string> command = {weft_program,
                                      "--headless",
                                      source_dir + "/tests/data/" + scene.file,
                                      "--quiet",
                                      "--out",
                                      out.string(),
                                      "--frames",
                                      std::to_string(scene.frames)};
  command.insert(command.end(), more.begin(), more.end());
  const ProgramResult result = run_program(command, dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 0) << scene.file << ": " << result.error_text;
  EXPECT_TRUE(contains(result.error_text, ": starts tangled: ")) << scene.file << ": " << result.error_text;
  if (result_out != nullptr) *result_out = result;
  return {stats_column(out / "stats.csv", "intersecting_pairs"),
          stats_column(out / "stats.csv", "vertices_inside_colliders")};
}

TEST(Untangling, EveryTangledSceneIsCleanFromTheFirstFrameOn) {
  TempDir dir("weft_untangling");
  for (const TangledScene& scene : tangled_scenes) {
    const Counts counts = run_scene(scene, dir, {});
    ASSERT_EQ(counts.pairs.size(), static_cast<size_t>(scene.frames + 1)) << scene.file;
    EXPECT_GT(counts.pairs[0] + counts.inside[0], 0.0) << scene.file << " should start tangled";
    for (int frame = 1; frame <= scene.frames; ++frame) {
      EXPECT_EQ(counts.pairs[frame], 0.0) << scene.file << ", frame " << frame;
      EXPECT_EQ(counts.inside[frame], 0.0) << scene.file << ", frame " << frame;
    }
  }
}

TEST(Untangling, OffTheScenesStayTangled) {
  TempDir dir("weft_untangling_off");
  for (const TangledScene& scene : tangled_scenes) {
    const Counts counts = run_scene({scene.file, 2}, dir, {"--set", "collision.untangle=false"});
    ASSERT_EQ(counts.pairs.size(), 3u) << scene.file;
    EXPECT_GT(counts.pairs[2] + counts.inside[2], 0.0) << scene.file;
  }
}

TEST(Untangling, WorksWithTheBarrierResponseToo) {
  TempDir dir("weft_untangling_barrier");
  for (const TangledScene& scene : tangled_scenes) {
    const Counts counts = run_scene({scene.file, 3}, dir, {"--set", "collision.response=barrier"});
    ASSERT_EQ(counts.pairs.size(), 4u) << scene.file;
    for (int frame = 1; frame <= 3; ++frame) {
      EXPECT_EQ(counts.pairs[frame] + counts.inside[frame], 0.0) << scene.file << ", frame " << frame;
    }
  }
}

TEST(Untangling, ATangleArisingMidRunIsUndoneAfterTheStepThatMadeIt) {
  // A small sheet on a script is driven down at 2 m/s through a sheet pinned everywhere but at its
  // centre vertex: the collision response cannot move pins, the step ends unclean and leaves the
  // sheets crossed (untangling off: the exact check finds pairs). With untangling on, the step
  // after moves the free vertex back and every recorded frame is clean.
  TempDir dir("weft_untangling_mid_run");
  // Every vertex of the sheet is pinned but its centre, 40 (tests/data/pinned_punch.json).
  const std::string scene = source_dir + "/tests/data/pinned_punch.json";
  double pairs_off = 0.0;
  double pairs_on = 0.0;
  for (const bool untangle : {false, true}) {
    const fs::path out = dir.path() / (untangle ? "on" : "off");
    const ProgramResult result =
        run_program({weft_program, "--headless", scene, "--quiet", "--out", out.string(), "--set",
                     std::string("collision.untangle=") + (untangle ? "true" : "false")},
                    dir.file("log.txt"));
    ASSERT_EQ(result.exit_code, 0) << result.error_text;
    double& total = untangle ? pairs_on : pairs_off;
    for (const double pairs : stats_column(out / "stats.csv", "intersecting_pairs")) total += pairs;
    if (untangle) {
      double moved = 0.0;
      for (const double v : stats_column(out / "stats.csv", "untangled_vertices")) moved += v;
      EXPECT_GT(moved, 0.0);
    }
  }
  EXPECT_GT(pairs_off, 0.0);
  EXPECT_EQ(pairs_on, 0.0);
}

TEST(Untangling, AVertexPinnedInsideAColliderIsRefused) {
  TempDir dir("weft_pinned_inside");
  const std::string scene = source_dir + "/tests/data/sheet_in_sphere.json";
  // Vertex 528 is the middle of the 33 x 33 lattice, 4 cm inside the sphere.
  const ProgramResult result =
      run_program({weft_program, "--headless", scene, "--quiet", "--out", (dir.path() / "out").string(),
                   "--set", "cloths.0.pins.vertices=[528]"},
                  dir.file("log.txt"));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(contains(result.error_text, scene + ": /cloths/0/pins: vertex 528 of cloth 'sheet' is pinned "))
      << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "inside collider 'sphere' (/colliders/0)")) << result.error_text;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "stats.csv"));
  // Without untangling the same scene runs, the pin left where it is.
  const ProgramResult off = run_program(
      {weft_program, "--headless", scene, "--quiet", "--out", (dir.path() / "off").string(), "--set",
       "cloths.0.pins.vertices=[528]", "--set", "collision.untangle=false", "--frames", "1"},
      dir.file("log_off.txt"));
  EXPECT_EQ(off.exit_code, 0) << off.error_text;
}

}  // namespace
}  // namespace weft
