// `weft plot DIR` writes energy.png and time.png with gnuplot (skipped where gnuplot is missing).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string drape_scene = std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json";

bool is_png(const fs::path& path) {
  const std::string bytes = read_bytes(path);
  return bytes.size() > 1000 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

TEST(Plot, WritesEnergyAndTimePngs) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot is not installed";
  TempDir dir("weft_plot");
  const fs::path out = dir.path() / "run";
  ASSERT_EQ(run_program({weft_program, "--headless", drape_scene, "--out", out.string(), "--quiet",
                         "--frames", "5", "--set", "cloths.0.grid.resolution=[8,8]"},
                        dir.file("run.txt"))
                .exit_code,
            0);
  const auto result = run_program({weft_program, "plot", out.string()}, dir.file("plot.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_TRUE(is_png(out / "energy.png"));
  EXPECT_TRUE(is_png(out / "time.png"));
  EXPECT_FALSE(has_temporary_files(out));
}

TEST(Plot, AFolderWithoutStatsIsAnError) {
  TempDir dir("weft_plot_empty");
  const auto result = run_program({weft_program, "plot", dir.path().string()}, dir.file("plot.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("expected a run folder with stats.csv"), std::string::npos)
      << result.error_text;
}

TEST(Plot, AGarbageStatsFileIsNamedWithItsLineBeforeGnuplot) {
  TempDir dir("weft_plot_garbage");
  std::ofstream(dir.path() / "stats.csv") << "hello,world\n1,2\n";
  auto result = run_program({weft_program, "plot", dir.path().string()}, dir.file("header.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find(
                "stats.csv: line 1: expected the stats header of a weft run, with a \"frame\" column"),
            std::string::npos)
      << result.error_text;

  // A real run's stats with a damaged row.
  const fs::path out = dir.path() / "run";
  ASSERT_EQ(run_program({weft_program, "--headless", drape_scene, "--out", out.string(), "--quiet",
                         "--frames", "2", "--set", "cloths.0.grid.resolution=[6,6]"},
                        dir.file("run.txt"))
                .exit_code,
            0);
  std::ofstream(out / "stats.csv", std::ios::app) << "3,0.1,\x01\xff,garbage\n";
  result = run_program({weft_program, "plot", out.string()}, dir.file("row.txt"));
  EXPECT_EQ(result.exit_code, 2);
  // As many numbers as the header has columns (the count grows with stats.csv's columns).
  EXPECT_NE(result.error_text.find("stats.csv: line 5: expected "), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find(" comma-separated numbers (one per header column), got 4 fields"),
            std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out / "energy.png"));
}

}  // namespace
}  // namespace weft
