// Sweep files: the grid expands to every combination in file order, cases are named by their
// values, and bad files are refused naming the file, the field and what was expected.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "io/sweep_file.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

using testing::TempDir;

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.file(name)) << text;
  return dir.file(name);
}

std::string error_of(const std::string& path) {
  try {
    load_sweep_file(path);
  } catch (const SceneError& error) {
    return error.what();
  }
  return "";
}

TEST(SweepFile, GridExpandsToEveryCombinationLastKeyFastest) {
  TempDir dir("weft_sweep_file");
  const std::string path = write(dir, "drape.json", R"({
    "scene": "scenes/drape.json",
    "frames": 12,
    "set": ["cloths.0.grid.resolution=[8,8]"],
    "grid": {"cloths.0.springs.structural.stiffness": [200, 500.5],
             "solver.integrator": ["symplectic_euler", "midpoint", "implicit_euler"]}
  })");
  const SweepDesc sweep = load_sweep_file(path);
  EXPECT_EQ(sweep.name, "drape");
  EXPECT_EQ(sweep.scene, (dir.path() / "scenes/drape.json").string());
  EXPECT_EQ(sweep.out, "out/drape");
  EXPECT_EQ(sweep.frames, 12);
  EXPECT_EQ(sweep.checkpoint_every, 10);  // sweeps checkpoint unless told not to
  const std::vector<SweepCase> cases = expand_sweep(sweep);
  ASSERT_EQ(cases.size(), 6u);
  EXPECT_EQ(cases[0].name, "000_stiffness-200_integrator-symplectic_euler");
  EXPECT_EQ(cases[1].name, "001_stiffness-200_integrator-midpoint");
  EXPECT_EQ(cases[5].name, "005_stiffness-500.5_integrator-implicit_euler");
  EXPECT_EQ(cases[4].overrides, (std::vector<std::string>{"cloths.0.grid.resolution=[8,8]",
                                                          "cloths.0.springs.structural.stiffness=500.5",
                                                          "solver.integrator=\"midpoint\""}));
}

TEST(SweepFile, NamesUseLongerPathTailsWhenShortOnesClash) {
  TempDir dir("weft_sweep_names");
  const std::string path = write(dir, "s.json", R"({
    "scene": "/abs/scene.json", "name": "springs",
    "grid": {"cloths.0.springs.structural.stiffness": [1], "cloths.0.springs.shear.stiffness": [2, 3],
             "cloths.0.grid.resolution": [[16, 16]]}
  })");
  const std::vector<SweepCase> cases = expand_sweep(load_sweep_file(path));
  ASSERT_EQ(cases.size(), 2u);
  EXPECT_EQ(cases[1].name, "001_structural.stiffness-1_shear.stiffness-3_resolution-16_16");
  EXPECT_EQ(load_sweep_file(path).scene, "/abs/scene.json");
}

// A grid of 40 keys with two values each is 2^40 cases: expand_sweep ran out of memory writing
// their names. The sweep file is refused at the key where the product passes max_sweep_cases.
TEST(SweepFile, GridsWithMoreCasesThanTheBoundAreRefusedAtTheKeyThatPassesIt) {
  TempDir dir("weft_sweep_huge");
  std::string grid;
  for (int k = 0; k < 40; ++k)
    grid += (k ? ", " : "") + std::string("\"k") + std::to_string(k) + "\": [1, 2]";
  const std::string message =
      error_of(write(dir, "huge.json", R"({"scene": "s.json", "grid": {)" + grid + "}}"));
  // 2^17 = 131072 is the first power of two past 100000.
  EXPECT_NE(message.find("huge.json: /grid/k16: the grid has more than 100000 combinations"),
            std::string::npos)
      << message;

  // Up to the bound is fine: 10 x 10 x 1000 cases.
  std::string values;
  for (int v = 0; v < 1000; ++v) values += (v ? ", " : "") + std::to_string(v);
  const SweepDesc sweep = load_sweep_file(
      write(dir, "bound.json",
            R"({"scene": "s.json", "grid": {"a": [0,1,2,3,4,5,6,7,8,9], "b": [0,1,2,3,4,5,6,7,8,9], "c": [)" +
                values + "]}}"));
  EXPECT_EQ(expand_sweep(sweep).size(), static_cast<size_t>(max_sweep_cases));
}

TEST(SweepFile, BadFilesNameTheFieldAndWhatWasExpected) {
  TempDir dir("weft_sweep_bad");
  EXPECT_NE(error_of(write(dir, "a.json", R"({"scene": "s.json", "grid": {"x": [1]}, "thread": 2})"))
                .find("a.json: /thread: unknown key \"thread\""),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "b.json", R"({"grid": {"x": [1]}})")).find("b.json: /scene: missing"),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "c.json", R"({"scene": "s.json", "grid": {"x": []}})"))
                .find("c.json: /grid/x: expected a non-empty array of values"),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "d.json", R"({"scene": "s.json", "grid": {"x": [1]}, "threads": 0})"))
                .find("d.json: /threads: expected an integer >= 1 and <= 256, got 0"),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "d2.json", R"({"scene": "s.json", "grid": {"x": [1]}, "threads": 100000})"))
                .find("d2.json: /threads: expected an integer >= 1 and <= 256, got 100000"),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "e.json", R"({"scene": "s.json", "grid": {"x": [1]}, "format": "abc"})"))
                .find("e.json: /format: expected \"pc2\", \"obj\" or \"both\""),
            std::string::npos);
  EXPECT_NE(
      error_of(write(dir, "f.json", R"({"scene": "s.json", "grid": {"x": [1]}, "slurm": {"mem": "1G"}})"))
          .find("f.json: /slurm/mem: unknown key"),
      std::string::npos);
  EXPECT_NE(error_of(write(dir, "g.json", R"({"scene": "s.json", "grid": {"x": [1]}, "set": ["novalue"]})"))
                .find("g.json: /set/0: expected \"path=value\""),
            std::string::npos);
  EXPECT_NE(error_of(write(dir, "h.json", "{not json")).find("h.json: /: invalid JSON"), std::string::npos);
}

}  // namespace
}  // namespace weft
