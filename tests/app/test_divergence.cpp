// A run that goes wrong stops with exit code 3 and a diagnostic naming the frame, the vertex
// and the term; the frames and checkpoint written before stay whole; summary.json says why.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/point_cache.hpp"
#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string default_scene = std::string(WEFT_SOURCE_DIR) + "/scenes/default.json";

std::vector<std::string> stiff_cloth(const fs::path& out, int frames, const std::vector<std::string>& more) {
  std::vector<std::string> command = {weft_program,
                                      "--headless",
                                      default_scene,
                                      "--out",
                                      out.string(),
                                      "--quiet",
                                      "--frames",
                                      std::to_string(frames),
                                      "--checkpoint-every",
                                      "1",
                                      "--set",
                                      "cloths.0.grid.resolution=[8,8]",
                                      "--set",
                                      "cloths.0.springs.structural.stiffness=1e9",
                                      "--set",
                                      "solver.time_step=0.004"};
  command.insert(command.end(), more.begin(), more.end());
  return command;
}

void expect_last_good_frame_kept(const fs::path& out) {
  const auto run = read_json(out / "run.json");
  EXPECT_EQ(run["status"], "diverged");
  const int written = run["frames_written"];
  EXPECT_EQ(static_cast<int>(read_point_cache((out / "cloth.pc2").string()).samples.size()), written);
  EXPECT_TRUE(fs::exists(out / "cloth.rest.obj"));
  EXPECT_FALSE(has_temporary_files(out));
}

TEST(Divergence, SpeedPastTheBoundStops) {
  TempDir dir("weft_diverge_speed");
  const fs::path out = dir.path() / "run";
  const auto result = run_program(stiff_cloth(out, 60, {}), dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 3) << result.error_text;
  EXPECT_NE(result.error_text.find("diverged in frame"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("vertex"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("past the bound (--max-speed)"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("from the term \"structural springs\""), std::string::npos)
      << result.error_text;
  const auto summary = read_json(out / "summary.json");
  EXPECT_EQ(summary["status"], "diverged");
  EXPECT_EQ(summary["exit_code"], 3);
  EXPECT_EQ(summary["failure"]["quantity"], "speed");
  EXPECT_EQ(summary["failure"]["term"], "structural springs");
  EXPECT_GE(summary["failure"]["vertex"].get<int>(), 0);
  expect_last_good_frame_kept(out);
}

TEST(Divergence, NonFiniteStateStopsWhenBoundsAreOff) {
  TempDir dir("weft_diverge_nan");
  const fs::path out = dir.path() / "run";
  const auto result =
      run_program(stiff_cloth(out, 400, {"--max-speed", "0", "--max-strain", "0"}), dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 3) << result.error_text;
  EXPECT_NE(result.error_text.find("has a non-finite"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("term"), std::string::npos) << result.error_text;
  const auto summary = read_json(out / "summary.json");
  EXPECT_TRUE(summary["failure"]["quantity"] == "position" || summary["failure"]["quantity"] == "velocity");
  EXPECT_TRUE(summary["failure"]["value"].is_null());
  // The last checkpoint is kept (and still readable: a resume of it diverges the same way).
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
  expect_last_good_frame_kept(out);
}

TEST(Divergence, StrainPastTheBoundStops) {
  TempDir dir("weft_diverge_strain");
  const fs::path out = dir.path() / "run";
  const auto result =
      run_program({weft_program, "--headless", default_scene, "--out", out.string(), "--quiet", "--frames",
                   "30", "--set", "cloths.0.grid.resolution=[8,8]", "--max-strain", "0.0005"},
                  dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 3) << result.error_text;
  EXPECT_NE(result.error_text.find("stretched"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("past the bound (--max-strain)"), std::string::npos) << result.error_text;
  EXPECT_EQ(read_json(out / "summary.json")["failure"]["quantity"], "strain");
  expect_last_good_frame_kept(out);
}

TEST(Divergence, AdaptiveSteppingThatCannotMeetItsToleranceStopsAndSaysSo) {
  // min_step = max_step = 4 ms, ten times the default scene's explicit limit: no step the
  // controller may take meets 1 um, and the run stops instead of reporting a bounded error.
  TempDir dir("weft_diverge_adaptive");
  const fs::path out = dir.path() / "run";
  const auto result = run_program({weft_program, "--headless", default_scene, "--out", out.string(), "--quiet",
                                   "--frames", "5", "--set", "cloths.0.grid.resolution=[8,8]", "--set",
                                   "solver.adaptive={\"enabled\": true, \"tolerance\": 1e-6, \"min_step\": 0.004, "
                                   "\"max_step\": 0.004}"},
                                  dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 3) << result.error_text;
  EXPECT_NE(result.error_text.find("adaptive stepping could not meet solver.adaptive.tolerance"), std::string::npos)
      << result.error_text;
  EXPECT_EQ(read_json(out / "summary.json")["status"], "diverged");
  expect_last_good_frame_kept(out);
}

}  // namespace
}  // namespace weft
