// Checkpoints as a user meets them: a run killed with SIGKILL resumes from its last checkpoint
// and every frame, the point cache and colliders.csv come out byte-identical to an uninterrupted
// run; a resume with another scene or a damaged checkpoint is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string drape_scene = std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json";
constexpr int total_frames = 150;

std::vector<std::string> drape(const fs::path& out, int frames, const std::vector<std::string>& more = {}) {
  std::vector<std::string> command = {weft_program, "--headless",
                                      drape_scene,  "--out",
                                      out.string(), "--quiet",
                                      "--format",   "both",
                                      "--frames",   std::to_string(frames),
                                      "--set",      "cloths.0.grid.resolution=[20,20]"};
  command.insert(command.end(), more.begin(), more.end());
  return command;
}

std::string frame_name(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.obj", frame);
  return name;
}

TEST(CheckpointResume, KilledRunResumesBitIdentically) {
  TempDir dir("weft_resume");
  const fs::path reference = dir.path() / "reference", killed = dir.path() / "killed";
  ASSERT_EQ(run_program(drape(reference, total_frames), dir.file("reference.txt")).exit_code, 0);

  // Kill -9 once a checkpoint exists and a few frames past it are on disk.
  const std::string log = dir.file("killed.txt");
  const pid_t pid = start_program(drape(killed, total_frames, {"--checkpoint-every", "4"}), log);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for(killed / frame_name(10), std::chrono::seconds(60)));
  kill(pid, SIGKILL);
  const auto killed_result = wait_program(pid, log);
  ASSERT_EQ(killed_result.exit_code, 128 + SIGKILL) << "the run ended before it could be killed";
  EXPECT_EQ(read_json(killed / "run.json")["status"], "running");
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin"));

  // Resume with nothing but the folder: the scene comes from the recorded run.
  const auto resumed = run_program({weft_program, "--headless", "--resume", killed.string(), "--quiet",
                                    "--format", "both", "--checkpoint-every", "4"},
                                   dir.file("resumed.txt"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.error_text;
  EXPECT_EQ(read_json(killed / "run.json")["status"], "complete");

  for (int frame = 0; frame <= total_frames; ++frame) {
    const std::string name = frame_name(frame);
    const std::string expected = read_bytes(reference / name);
    ASSERT_FALSE(expected.empty()) << name;
    ASSERT_EQ(read_bytes(killed / name), expected) << name << " differs after the resume";
  }
  EXPECT_FALSE(fs::exists(killed / frame_name(total_frames + 1)));
  EXPECT_EQ(read_bytes(killed / "cloth.pc2"), read_bytes(reference / "cloth.pc2"));
  EXPECT_EQ(read_bytes(killed / "colliders.csv"), read_bytes(reference / "colliders.csv"));
  EXPECT_EQ(count_lines(killed / "stats.csv"), count_lines(reference / "stats.csv"));
  EXPECT_EQ(read_json(killed / "summary.json")["frames_written"], total_frames + 1);
  EXPECT_FALSE(has_temporary_files(killed));
}

// The closing line of a resumed run counts the steps that ended unconverged over the whole run,
// as summary.json does, not only over the frames run since the resume.
TEST(CheckpointResume, TheUnconvergedCountCoversTheWholeRun) {
  TempDir dir("weft_resume_unconverged");
  const fs::path out = dir.path() / "run";
  const auto first = run_program(
      drape(out, 14, {"--checkpoint-every", "7", "--set", "solver.newton.max_iterations=2"}), dir.file("a.txt"));
  ASSERT_EQ(first.exit_code, 0) << first.error_text;
  const int before = read_json(out / "summary.json")["unconverged_steps"].get<int>();
  ASSERT_GT(before, 0) << "the drape's contact steps should not converge in two Newton iterations";

  const auto resumed = run_program({weft_program, "--headless", "--resume", out.string(), "--quiet", "--frames", "18"},
                                   dir.file("b.txt"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.error_text;
  const int total = read_json(out / "summary.json")["unconverged_steps"].get<int>();
  EXPECT_GT(total, before);
  EXPECT_NE(resumed.error_text.find("weft: " + std::to_string(total) + " implicit Euler steps ended unconverged"),
            std::string::npos)
      << resumed.error_text;
  // It says what the unconverged steps did to the energy (the residual flow over the whole run)
  // and what the cap is.
  char residual[64];
  std::snprintf(residual, sizeof residual, "dissipated_residual %.3g J",
                read_json(out / "summary.json")["energy"]["dissipated_by"]["residual"].get<double>());
  EXPECT_NE(resumed.error_text.find(residual), std::string::npos) << resumed.error_text;
  EXPECT_NE(resumed.error_text.find("solver.newton.max_iterations (now 2)"), std::string::npos) << resumed.error_text;
}

// A checkpoint written before a scene key existed (here `bending.model`) resumes:
// the missing key compares at its default, which is what the run used.
TEST(CheckpointResume, ACheckpointFromBeforeANewSceneKeyResumes) {
  TempDir dir("weft_resume_older");
  const fs::path out = dir.path() / "run";
  ASSERT_EQ(run_program(drape(out, 8, {"--checkpoint-every", "4"}), dir.file("a.txt")).exit_code, 0);
  const std::string path = (out / "checkpoint.bin").string();
  Checkpoint checkpoint = read_checkpoint(path);
  nlohmann::json scene = nlohmann::json::parse(checkpoint.scene_json);
  ASSERT_TRUE(scene["cloths"][0]["bending"].contains("model"));
  scene["cloths"][0]["bending"].erase("model");
  checkpoint.scene_json = scene.dump();
  write_checkpoint(path, checkpoint);

  const auto resumed =
      run_program({weft_program, "--headless", "--resume", out.string(), "--quiet", "--frames", "10"}, dir.file("b.txt"));
  EXPECT_EQ(resumed.exit_code, 0) << resumed.error_text;
  EXPECT_EQ(read_json(out / "summary.json")["frames_written"], 11);
}

TEST(CheckpointResume, ADifferentSceneOrADamagedCheckpointIsRefused) {
  TempDir dir("weft_resume_refused");
  const fs::path out = dir.path() / "run";
  ASSERT_EQ(run_program(drape(out, 8, {"--checkpoint-every", "4"}), dir.file("a.txt")).exit_code, 0);
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin"));
  const std::string pc2_before = read_bytes(out / "cloth.pc2");

  auto result =
      run_program({weft_program, "--headless", drape_scene, "--resume", out.string(), "--quiet", "--set",
                   "cloths.0.grid.resolution=[20,20]", "--set", "cloths.0.mass_damping=0.5"},
                  dir.file("b.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find(
                "checkpoint.bin: the scene differs from the checkpoint's at /cloths/0/mass_damping"),
            std::string::npos)
      << result.error_text;
  EXPECT_EQ(read_bytes(out / "cloth.pc2"), pc2_before);  // untouched

  {
    std::fstream file(out / "checkpoint.bin", std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(200);
    file.put('\x01');
  }
  result = run_program({weft_program, "--headless", "--resume", out.string(), "--quiet"}, dir.file("c.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("checkpoint.bin: checkpoint checksum: mismatch"), std::string::npos)
      << result.error_text;

  result = run_program({weft_program, "--headless", "--resume", (dir.path() / "nothing").string(), "--quiet"},
                       dir.file("d.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("no checkpoint to resume from"), std::string::npos) << result.error_text;
}

TEST(CheckpointResume, ResumeKeepsTheRecordedFormat) {
  TempDir dir("weft_resume_format");
  const fs::path out = dir.path() / "run";
  std::vector<std::string> first = drape(out, 8, {"--checkpoint-every", "4"});
  first[std::find(first.begin(), first.end(), "both") - first.begin()] = "pc2";
  ASSERT_EQ(run_program(first, dir.file("a.txt")).exit_code, 0);
  const std::string pc2_before = read_bytes(out / "cloth.pc2");

  // Another format would mix OBJ frames into a point-cache recording: refused, nothing written.
  auto result = run_program(
      {weft_program, "--headless", "--resume", out.string(), "--quiet", "--format", "obj", "--frames", "12"},
      dir.file("b.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(
      result.error_text.find("run.json: the run was recorded with --format pc2; resume it with --format pc2 "
                             "(or without --format), not obj"),
      std::string::npos)
      << result.error_text;
  EXPECT_EQ(read_bytes(out / "cloth.pc2"), pc2_before);
  EXPECT_FALSE(fs::exists(out / frame_name(0)));

  // The same format, or none, goes on in the recorded one.
  result = run_program({weft_program, "--headless", "--resume", out.string(), "--quiet", "--frames", "12"},
                       dir.file("c.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_EQ(read_json(out / "run.json")["format"], "pc2");
  EXPECT_FALSE(fs::exists(out / frame_name(12)));
  result = run_program(
      {weft_program, "--headless", "--resume", out.string(), "--quiet", "--format", "pc2", "--frames", "16"},
      dir.file("d.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
}

TEST(CheckpointResume, ARunningRecordingCannotBeResumedBeside) {
  TempDir dir("weft_resume_locked");
  const fs::path out = dir.path() / "run";
  const pid_t first = start_program(drape(out, 100000, {"--checkpoint-every", "1"}), dir.file("first.txt"));
  ASSERT_GT(first, 0);
  ASSERT_TRUE(wait_for(out / "checkpoint.bin", std::chrono::seconds(120)));
  const auto result =
      run_program({weft_program, "--headless", "--resume", out.string(), "--quiet"}, dir.file("second.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("in use by another weft run (pid " + std::to_string(first) + " on host "),
            std::string::npos)
      << result.error_text;
  ::kill(first, SIGINT);
  EXPECT_EQ(wait_program(first, dir.file("first.txt")).exit_code, 130);
  EXPECT_FALSE(fs::exists(out / ".weft.lock"));  // released on the interrupted path too
}

// Every term that carries state or depends on time: plastic membrane (its rest shapes flow),
// bending, wind and drag, a moving pin group (it follows the time), implicit Euler. A run
// stopped at frame 12 and extended from its checkpoint to 24 frames records the same bytes as
// one run of 24 frames.
TEST(CheckpointResume, PlasticityMovingPinsAndWindResumeBitIdentically) {
  TempDir dir("weft_resume_terms");
  const std::string scene = dir.file("terms.json");
  std::ofstream(scene) << R"({
    "solver": {"integrator": "implicit_euler", "time_step": 0.005},
    "fps": 50,
    "wind": [1.5, 0, 0.5],
    "cloths": [{"name": "flag", "grid": {"size": [1, 1], "resolution": [8, 8]},
                "springs": {"structural": {"stiffness": 0, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}},
                "membrane": {"young_modulus": 3000, "yield_strain": 0.005, "plastic_flow": 0.3},
                "bending": {"stiffness": 0.001},
                "air_drag": {"normal": 0.5, "tangential": 0.05},
                "pins": {"corners": ["top_left"]},
                "moving_pins": [{"corners": ["top_right"], "velocity": [0.2, 0, 0]}]}]
  })";
  const auto run = [&](const fs::path& out, int frames, const std::vector<std::string>& more) {
    std::vector<std::string> command = {weft_program, "--headless", scene,      "--out",
                                        out.string(), "--quiet",    "--frames", std::to_string(frames)};
    command.insert(command.end(), more.begin(), more.end());
    return run_program(command, dir.file("log.txt"));
  };
  const fs::path reference = dir.path() / "reference", resumed = dir.path() / "resumed";
  ASSERT_EQ(run(reference, 24, {}).exit_code, 0);
  ASSERT_EQ(run(resumed, 12, {"--checkpoint-every", "4"}).exit_code, 0);
  const auto result = run_program({weft_program, "--headless", "--resume", resumed.string(), "--quiet",
                                   "--frames", "24", "--checkpoint-every", "4"},
                                  dir.file("resume.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;

  EXPECT_TRUE(read_bytes(resumed / "flag.pc2") == read_bytes(reference / "flag.pc2"))
      << "flag.pc2 differs after the resume";
  // The scene did yield (otherwise the rest shapes would not need saving).
  std::ifstream stats(reference / "stats.csv");
  std::string header, row;
  std::getline(stats, header);
  const size_t column = std::count(header.begin(), header.begin() + header.find("yielded_triangles"), ',');
  long long yielded = 0;
  while (std::getline(stats, row)) {
    size_t at = 0;
    for (size_t c = 0; c < column; ++c) at = row.find(',', at) + 1;
    yielded += std::atoll(row.c_str() + at);
  }
  EXPECT_GT(yielded, 0);
}

}  // namespace
}  // namespace weft
