// Bad input as a user gives it to the weft program: each case ends with exit 2 and a message
// naming the file, the JSON path or option, and what was expected, before anything is written;
// none aborts, hangs or runs with a silently different setting.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using testing::contains;
using testing::ProgramResult;
using testing::run_program;
using testing::TempDir;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;
const std::string default_scene = source_dir + "/scenes/default.json";
const std::string drape_scene = source_dir + "/scenes/drape_sphere.json";

// Runs weft with `arguments` (no display, so a viewer run fails fast if it gets that far).
ProgramResult weft(const TempDir& dir, std::vector<std::string> arguments) {
  static int runs = 0;
  arguments.insert(arguments.begin(),
                   {"/usr/bin/env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", weft_program});
  return run_program(arguments, dir.file("log" + std::to_string(runs++) + ".txt"));
}

TEST(BadInput, AFolderAsSceneOrSweepFileIsRefused) {
  TempDir dir("weft_folder_scene");
  const std::string scenes = source_dir + "/scenes";
  const fs::path out = dir.path() / "out";
  for (const auto& arguments : std::vector<std::vector<std::string>>{
           {"--headless", scenes, "--out", out.string()}, {scenes + "/"}, {"sweep", scenes + "/"}}) {
    const ProgramResult result = weft(dir, arguments);
    EXPECT_EQ(result.exit_code, 2) << result.error_text;
    EXPECT_TRUE(contains(result.error_text, "scenes")) << result.error_text;
    EXPECT_TRUE(contains(result.error_text, "is a folder; expected a s")) << result.error_text;
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInput, ThreadCountOutOfRangeIsRefused) {
  TempDir dir("weft_threads");
  const fs::path out = dir.path() / "out";
  for (const std::string threads : {"100000", "2000", "-1", "four"}) {
    const ProgramResult result =
        weft(dir, {"--headless", default_scene, "--out", out.string(), "--threads", threads});
    EXPECT_EQ(result.exit_code, 2) << threads << ": " << result.error_text;
    EXPECT_TRUE(contains(
        result.error_text,
        "--threads: expected a whole number of threads from 0 (all cores) to 256, got '" + threads + "'"))
        << result.error_text;
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInput, NumericOptionsSayTheirRange) {
  TempDir dir("weft_options");
  ProgramResult result = weft(dir, {"--frames", "abc"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text,
                       "--frames: expected a whole number of frames >= 0 and <= 10000000, got 'abc'"))
      << result.error_text;
  EXPECT_FALSE(contains(result.error_text, "1797")) << result.error_text;

  result = weft(dir, {"sweep", source_dir + "/sweeps/drape_stiffness.json", "--jobs", "0"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(
      contains(result.error_text, "--jobs: expected a whole number of runs at once from 1 to 1024, got '0'"))
      << result.error_text;

  result = weft(dir, {"--headless", default_scene, "--out", dir.file("out"), "--max-speed", "fast"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(
      contains(result.error_text, "--max-speed: expected a speed in m/s >= 0 (0: no bound), got 'fast'"))
      << result.error_text;
}

TEST(BadInput, StepCountsARunCannotFinishAreRefused) {
  TempDir dir("weft_steps");
  const fs::path out = dir.path() / "out";
  // 1e-12 s steps would overflow the int step count and run silently at h = 1/30 s.
  ProgramResult result =
      weft(dir, {"--headless", drape_scene, "--out", out.string(), "--set", "solver.time_step=1e-12"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(
      result.error_text,
      "--set solver.time_step=1e-12: /solver/time_step: expected a time step of at least 3.333e-08 s "
      "at 30 fps, got 1e-12"))
      << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "more than the 1000000")) << result.error_text;

  result = weft(dir, {"--headless", drape_scene, "--out", out.string(), "--set", "solver.time_step=2e-11"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "/solver/time_step: expected a time step of at least"))
      << result.error_text;

  result = weft(dir, {"--headless", default_scene, "--out", out.string(), "--set", "solver.substeps=100000"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text,
                       "--set solver.substeps=100000: /solver/substeps: expected at most 12500 substeps with "
                       "80 steps per frame, "
                       "got 100000"))
      << result.error_text;

  result = weft(dir, {"--headless", default_scene, "--out", out.string(), "--set", "cloths.0.thickness=1e9"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(
      result.error_text,
      "--set cloths.0.thickness=1e9: /cloths/0/thickness: expected a contact thickness of at most 0.2828 m"))
      << result.error_text;

  result = weft(dir, {"--headless", default_scene, "--out", out.string(), "--set", "fps=1e300"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(
      contains(result.error_text, "--set fps=1e300: /fps: expected a number in [1, 10000], got 1e+300"))
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));
}

TEST(BadInput, SetBeforeTheSceneTakesOneValue) {
  TempDir dir("weft_set_first");
  const fs::path out = dir.path() / "out";
  const ProgramResult result =
      weft(dir, {"--headless", "--set", "fps=30", "--set", "cloths.0.grid.resolution=[6,6]", default_scene,
                 "--out", out.string(), "--frames", "1", "--quiet"});
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_TRUE(fs::exists(out / "run.json"));
}

TEST(BadInput, BinarySceneFileIsQuotedEscaped) {
  TempDir dir("weft_binary_scene");
  const std::string scene = dir.file("picture.json");
  std::ofstream(scene, std::ios::binary) << std::string("\x89PNG\r\n\x1a\n\x00\x01", 10);
  const ProgramResult result = weft(dir, {"--headless", scene, "--out", dir.file("out")});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "picture.json: /: invalid JSON")) << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "\\x89")) << result.error_text;
  for (const char c : result.error_text) {
    const auto byte = static_cast<unsigned char>(c);
    EXPECT_TRUE(c == '\n' || (byte >= 0x20 && byte < 0x7f))
        << "raw byte " << int(byte) << " in: " << result.error_text;
  }
}

TEST(BadInput, SceneTooLargeForMemoryIsRefused) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than ulimit -v leaves";
#endif
  TempDir dir("weft_memory");
  const fs::path out = dir.path() / "out";
  // Under a 4 GB address-space limit, the estimate refuses a 4096 x 4096 grid before building it.
  ProgramResult result =
      run_program({"/bin/sh", "-c",
                   "ulimit -v 4000000 && exec " + weft_program + " --headless " + default_scene + " --out " +
                       out.string() + " --set 'cloths.0.grid.resolution=[4096,4096]'"},
                  dir.file("estimate.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(
      result.error_text,
      "--set cloths.0.grid.resolution=[4096,4096]: /cloths/0/grid/resolution: the scene needs about 20.1 GB"))
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));

  // One the estimate lets through but the limit does not: std::bad_alloc (here in an OpenMP
  // region) ends in the same clear message and exit 2, not an abort.
  result =
      run_program({"/bin/sh", "-c",
                   "ulimit -v 1400000 && exec " + weft_program + " --headless " + default_scene + " --out " +
                       out.string() + " --quiet --frames 1 --set 'cloths.0.grid.resolution=[1024,1024]'"},
                  dir.file("bad_alloc.txt"));
  EXPECT_EQ(result.exit_code, 2) << result.error_text;
  EXPECT_TRUE(contains(result.error_text,
                       "weft: out of memory: the scene needs more memory than this process may use"))
      << result.error_text;
}

// A one-cloth scene on `obj` with a mesh collider on `collider` (empty: none).
std::string mesh_scene(const TempDir& dir, const std::string& obj, const std::string& collider) {
  const std::string scene = dir.file("mesh_scene.json");
  std::ofstream(scene) << R"({"cloths": [{"obj": ")" << obj << R"("}], "colliders": [)"
                       << (collider.empty() ? "" : R"({"type": "mesh", "obj": ")" + collider + R"("})")
                       << "]}";
  return scene;
}

TEST(BadInput, DefectiveObjMeshesAreRefused) {
  TempDir dir("weft_bad_obj");
  const fs::path out = dir.path() / "out";
  std::ofstream(dir.file("quad.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
  // Vertices 2 and 3 at one point.
  std::ofstream(dir.file("zero_edge.obj")) << "v 0 0 0\nv 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n\nf 2 3 4\n";
  // Three triangles on the edge 1-2.
  std::ofstream(dir.file("fin.obj"))
      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
  // A collider triangle whose corners lie on one line.
  std::ofstream(dir.file("flat.obj")) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n";

  ProgramResult result =
      weft(dir, {"--headless", mesh_scene(dir, "zero_edge.obj", ""), "--out", out.string()});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "mesh_scene.json: /cloths/0/obj: ")) << result.error_text;
  EXPECT_TRUE(contains(result.error_text,
                       "zero_edge.obj: line 7: triangle 2 has a zero-length edge: vertices 2 and 3"))
      << result.error_text;

  result = weft(dir, {"--headless", mesh_scene(dir, "fin.obj", ""), "--out", out.string()});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "/cloths/0/obj: ")) << result.error_text;
  EXPECT_TRUE(contains(
      result.error_text,
      "fin.obj: the edge between vertices 1 and 2 is in 3 triangles (1, 2, 3); expected a manifold cloth"))
      << result.error_text;

  result = weft(dir, {"--headless", mesh_scene(dir, "quad.obj", "flat.obj"), "--out", out.string()});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "/colliders/0/obj: ")) << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "flat.obj: triangle 2 (vertices 1, 2, 3) has zero area"))
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace weft
