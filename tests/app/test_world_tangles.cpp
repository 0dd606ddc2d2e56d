// Every run checks its first frame: a scene that starts tangled is said on stderr (which cloths,
// how many pairs, where), and stats.csv and summary.json carry the counts per frame; a clean
// start says nothing and counts zeros. Through the weft program, on the scenes in tests/data.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;

ProgramResult run_headless(const std::string& scene, const fs::path& out, const TempDir& dir,
                           const std::vector<std::string>& more = {}) {
  std::vector<std::string> command = {weft_program, "--headless", scene, "--quiet", "--out", out.string()};
  command.insert(command.end(), more.begin(), more.end());
  return run_program(command, dir.file("log.txt"));
}

TEST(WorldTangles, SheetsPassingThroughEachOtherAreSaidAndCounted) {
  TempDir dir("weft_tangled_sheets");
  const fs::path out = dir.path() / "out";
  const std::string scene = source_dir + "/tests/data/tangled_sheets.json";
  const ProgramResult result = run_headless(scene, out, dir);
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_TRUE(contains(result.error_text, scene + ": starts tangled: cloths \"flat\" and \"tilted\": "))
      << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "intersecting triangle pairs (first: triangles "))
      << result.error_text;
  EXPECT_FALSE(contains(result.error_text, "inside collider")) << result.error_text;

  const std::vector<double> pairs = stats_column(out / "stats.csv", "intersecting_pairs");
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_GT(pairs[0], 0.0);
  EXPECT_EQ(stats_column(out / "stats.csv", "vertices_inside_colliders")[0], 0.0);
  const nlohmann::json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["tangles"]["first_frame"]["intersecting_pairs"].get<double>(), pairs[0]);
  EXPECT_GE(summary["tangles"]["max"]["intersecting_pairs"].get<double>(), pairs[0]);
  // The count said on stderr is frame 0's.
  EXPECT_TRUE(
      contains(result.error_text, ": " + std::to_string(static_cast<int>(pairs[0])) + " intersecting"))
      << result.error_text;
}

TEST(WorldTangles, ASheetStartingInsideASphereIsSaidAndCounted) {
  TempDir dir("weft_sheet_in_sphere");
  const fs::path out = dir.path() / "out";
  const std::string scene = source_dir + "/tests/data/sheet_in_sphere.json";
  const ProgramResult result = run_headless(scene, out, dir);
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_TRUE(contains(result.error_text, "vertices inside collider \"sphere\" (deepest: vertex "))
      << result.error_text;
  // The middle starts 4 cm inside; the deepest vertex lies just off the middle.
  const size_t deepest = result.error_text.find("(deepest: vertex ");
  ASSERT_NE(deepest, std::string::npos);
  const size_t comma = result.error_text.find(", ", deepest);
  const double depth_cm = std::stod(result.error_text.substr(comma + 2));
  EXPECT_GT(depth_cm, 3.5);
  EXPECT_LE(depth_cm, 4.0);

  const std::vector<double> inside = stats_column(out / "stats.csv", "vertices_inside_colliders");
  ASSERT_FALSE(inside.empty());
  EXPECT_GT(inside[0], 0.0);
  EXPECT_TRUE(contains(result.error_text, "cloth \"sheet\": " + std::to_string(static_cast<int>(inside[0])) +
                                              " vertices inside collider"))
      << result.error_text;
  EXPECT_EQ(
      read_json(out / "summary.json")["tangles"]["first_frame"]["vertices_inside_colliders"].get<double>(),
      inside[0]);
}

TEST(WorldTangles, ACleanShippedSceneSaysNothingAndCountsZeros) {
  TempDir dir("weft_clean_start");
  const fs::path out = dir.path() / "out";
  const ProgramResult result = run_headless(source_dir + "/scenes/two_sheets.json", out, dir,
                                            {"--frames", "3", "--set", "cloths.0.grid.resolution=[12,12]",
                                             "--set", "cloths.1.grid.resolution=[12,12]"});
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_FALSE(contains(result.error_text, "tangled")) << result.error_text;
  for (const char* column : {"intersecting_pairs", "vertices_inside_colliders"}) {
    for (const double value : stats_column(out / "stats.csv", column)) EXPECT_EQ(value, 0.0) << column;
  }
  const nlohmann::json tangles = read_json(out / "summary.json")["tangles"];
  EXPECT_EQ(tangles["max"]["intersecting_pairs"].get<double>(), 0.0);
  EXPECT_EQ(tangles["max"]["vertices_inside_colliders"].get<double>(), 0.0);
}

}  // namespace
}  // namespace weft
