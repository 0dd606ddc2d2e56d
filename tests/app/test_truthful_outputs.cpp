// What a run leaves and says, checked through the weft program: a run into another run's folder
// says that it replaces it, and neither it nor a resume leaves a summary.json of the earlier run
// when killed; errors name the --set override or the whole path of the file that is missing.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

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
const std::string drape_scene = source_dir + "/scenes/drape_sphere.json";

std::vector<std::string> drape(const std::vector<std::string>& more) {
  std::vector<std::string> command = {
      weft_program, "--headless", drape_scene, "--quiet",
      "--format",   "both",       "--set",     "cloths.0.grid.resolution=[20,20]"};
  command.insert(command.end(), more.begin(), more.end());
  return command;
}

// Starts `command`, kills it with SIGKILL once `file` exists, and returns what it wrote to stderr.
std::string kill_when(const std::vector<std::string>& command, const fs::path& file, const std::string& log) {
  const pid_t pid = start_program(command, log);
  EXPECT_GT(pid, 0);
  EXPECT_TRUE(wait_for(file, std::chrono::seconds(60))) << file;
  kill(pid, SIGKILL);
  const ProgramResult result = wait_program(pid, log);
  EXPECT_EQ(result.exit_code, 128 + SIGKILL) << "the run ended before it could be killed";
  return result.error_text;
}

TEST(TruthfulOutputs, ARunIntoAnotherRunsFolderSaysSoAndAKillLeavesNoSummaryOfTheOldRun) {
  TempDir dir("weft_replaced_run");
  const fs::path out = dir.path() / "out";
  const ProgramResult first =
      run_program(drape({"--out", out.string(), "--frames", "3"}), dir.file("first.txt"));
  ASSERT_EQ(first.exit_code, 0) << first.error_text;
  ASSERT_EQ(read_json(out / "summary.json")["status"], "complete");
  EXPECT_FALSE(contains(first.error_text, "replacing")) << first.error_text;

  const std::string said = kill_when(drape({"--out", out.string(), "--frames", "150"}),
                                     out / "frame_0010.obj", dir.file("second.txt"));
  EXPECT_TRUE(contains(said, out.string() + ": replacing an earlier run (complete, 4 frames written)"))
      << said;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(read_json(out / "run.json")["status"], "running");
}

TEST(TruthfulOutputs, AKilledResumeLeavesNoSummaryOfTheRunsFirstPart) {
  TempDir dir("weft_killed_resume");
  const fs::path out = dir.path() / "out";
  const ProgramResult first = run_program(
      drape({"--out", out.string(), "--frames", "6", "--checkpoint-every", "3"}), dir.file("first.txt"));
  ASSERT_EQ(first.exit_code, 0) << first.error_text;
  ASSERT_EQ(read_json(out / "summary.json")["status"], "complete");

  // Extended past its end: the summary of frames 0..6 must not outlive the resume.
  const std::string said = kill_when({weft_program, "--headless", "--resume", out.string(), "--quiet",
                                      "--frames", "150", "--checkpoint-every", "3"},
                                     out / "frame_0012.obj", dir.file("resume.txt"));
  EXPECT_FALSE(contains(said, "replacing")) << said;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_EQ(read_json(out / "run.json")["status"], "running");
}

TEST(TruthfulOutputs, ErrorsOfASetOverrideNameTheOverrideNotTheSceneFile) {
  TempDir dir("weft_set_error");
  const fs::path out = dir.path() / "out";
  ProgramResult result = run_program(
      {weft_program, "--headless", drape_scene, "--out", out.string(), "--set", "solver.timestep=0.001"},
      dir.file("key.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "weft: --set solver.timestep=0.001: /solver/timestep: unknown key"))
      << result.error_text;
  EXPECT_FALSE(contains(result.error_text, "drape_sphere.json")) << result.error_text;

  result = run_program({weft_program, "--headless", drape_scene, "--out", out.string(), "--set", "fps=0"},
                       dir.file("value.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(contains(result.error_text, "weft: --set fps=0: /fps: expected a number in [1, 10000], got 0"))
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));
}

TEST(TruthfulOutputs, AMissingFileIsNamedByTheWholePathTried) {
  TempDir dir("weft_missing_obj");
  fs::create_directories(dir.path() / "scenes");
  std::ofstream(dir.path() / "scenes" / "shirt.json") << R"({"cloths": [{"obj": "shirt.obj"}]})";
  // From the folder above, with a relative scene path: the OBJ is looked for beside the scene.
  const ProgramResult result = run_program({"/bin/sh", "-c",
                                            "cd '" + dir.path().string() + "' && exec '" + weft_program +
                                                "' --headless scenes/shirt.json --out out"},
                                           dir.file("obj.txt"));
  EXPECT_EQ(result.exit_code, 2);
  const std::string tried = (fs::canonical(dir.path()) / "scenes" / "shirt.obj").string();
  EXPECT_TRUE(contains(result.error_text, "scenes/shirt.json: /cloths/0/obj: " + tried +
                                              ": cannot open file: No such file or directory"))
      << result.error_text;

  const ProgramResult scene = run_program(
      {"/bin/sh", "-c",
       "cd '" + dir.path().string() + "' && exec '" + weft_program + "' --headless nowhere.json --out out"},
      dir.file("scene.txt"));
  EXPECT_EQ(scene.exit_code, 2);
  EXPECT_TRUE(contains(scene.error_text, "nowhere.json: /: cannot open the scene file " +
                                             (fs::canonical(dir.path()) / "nowhere.json").string() +
                                             ": No such file or directory"))
      << scene.error_text;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

}  // namespace
}  // namespace weft
