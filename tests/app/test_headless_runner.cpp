// The headless runner as a user runs it: frames tinyobjloader reads back, stats and run.json,
// exit codes for bad input, divergence and unwritable output, and Ctrl-C leaving whole frames.
#include <gtest/gtest.h>
#include <tiny_obj_loader.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using testing::run_program;
using testing::TempDir;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;

struct ObjCounts {
  bool ok = false;
  size_t vertices = 0, normals = 0, texcoords = 0, triangles = 0;
};

ObjCounts read_back(const std::string& path) {
  tinyobj::ObjReader reader;
  ObjCounts counts;
  if (!reader.ParseFromFile(path)) return counts;
  counts.ok = true;
  counts.vertices = reader.GetAttrib().vertices.size() / 3;
  counts.normals = reader.GetAttrib().normals.size() / 3;
  counts.texcoords = reader.GetAttrib().texcoords.size() / 2;
  for (const auto& shape : reader.GetShapes()) counts.triangles += shape.mesh.num_face_vertices.size();
  return counts;
}

int count_lines(const std::string& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  return lines;
}

bool has_temporary_files(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename().string().find(".tmp.") != std::string::npos) return true;
  }
  return false;
}

TEST(HeadlessRunner, WritesFramesStatsAndRunJson) {
  TempDir dir("weft_headless");
  const fs::path out = dir.path() / "drape";
  const auto result = run_program({weft_program, "--headless", source_dir + "/scenes/drape_sphere.json", "--out",
                                   out.string(), "--frames", "5", "--format", "obj", "--set",
                                   "cloths.0.grid.resolution=[10,12]"},
                                  dir.file("log.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  for (int frame = 0; frame <= 5; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.obj", frame);
    const ObjCounts counts = read_back((out / name).string());
    ASSERT_TRUE(counts.ok) << name;
    EXPECT_EQ(counts.vertices, 120u) << name;
    EXPECT_EQ(counts.normals, 120u) << name;
    EXPECT_EQ(counts.texcoords, 120u) << name;
    EXPECT_EQ(counts.triangles, 2u * 9 * 11) << name;
  }
  EXPECT_FALSE(fs::exists(out / "frame_0006.obj"));
  EXPECT_EQ(count_lines((out / "stats.csv").string()), 1 + 6);
  std::ifstream run_file(out / "run.json");
  const auto run = nlohmann::json::parse(run_file);
  EXPECT_EQ(run["status"], "complete");
  EXPECT_EQ(run["frames_written"], 6);
  EXPECT_EQ(run["scene"]["frames"], 5);
  EXPECT_EQ(run["scene"]["cloths"][0]["grid"]["resolution"], nlohmann::json::array({10, 12}));
  EXPECT_FALSE(run["git_commit"].get<std::string>().empty());
  EXPECT_FALSE(has_temporary_files(out));
}

// stats.csv as rows of named columns.
std::vector<std::map<std::string, double>> read_stats(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream names(line);
  for (std::string name; std::getline(names, name, ',');) header.push_back(name);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::map<std::string, double> row;
    size_t c = 0;
    for (std::string field; std::getline(fields, field, ',') && c < header.size(); ++c) {
      row[header[c]] = std::strtod(field.c_str(), nullptr);
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(HeadlessRunner, StatsCarryAnEnergyBudgetThatClosesAcrossAResume) {
  // The drape: the cloth falls onto the sphere, the collision phase and implicit Euler trade
  // energy, and the budget closes in every row; a resumed run carries the flows on.
  TempDir dir("weft_headless_budget");
  const fs::path out = dir.path() / "drape";
  const std::vector<std::string> run = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                        "--quiet", "--checkpoint-every", "3", "--set",
                                        "cloths.0.grid.resolution=[10,10]", "--set",
                                        "cloths.0.transform.translation=[0,0.65,0]"};
  std::vector<std::string> first = run;
  first.insert(first.end(), {"--out", out.string(), "--frames", "6"});
  ASSERT_EQ(run_program(first, dir.file("first.txt")).exit_code, 0);
  std::vector<std::string> resume = run;
  resume.insert(resume.end(), {"--resume", out.string(), "--frames", "12"});
  ASSERT_EQ(run_program(resume, dir.file("resume.txt")).exit_code, 0);
  const auto rows = read_stats(out / "stats.csv");
  ASSERT_EQ(rows.size(), 13u);
  const double initial = rows[0].at("kinetic_energy") + rows[0].at("potential_energy");
  for (const auto& row : rows) {
    const double dissipated = row.at("dissipated_damping") + row.at("dissipated_integrator") +
                              row.at("dissipated_contact") + row.at("dissipated_plastic") +
                              row.at("dissipated_residual");
    EXPECT_NEAR(row.at("energy_dissipated"), dissipated, 1e-6 * std::abs(initial));
    const double error = row.at("kinetic_energy") + row.at("potential_energy") + dissipated - initial -
                         row.at("external_work");
    EXPECT_NEAR(row.at("budget_error"), error, 1e-6 * std::abs(initial));
    EXPECT_LT(std::abs(row.at("budget_error")), 0.01 * std::abs(initial)) << "frame " << row.at("frame");
  }
  EXPECT_GT(rows.back().at("dissipated_integrator"), 0.0);
  EXPECT_NE(rows.back().at("dissipated_contact"), 0.0) << "the cloth reached the sphere";
  std::ifstream summary_file(out / "summary.json");
  const auto summary = nlohmann::json::parse(summary_file);
  EXPECT_LT(summary["energy"]["budget_error_max"].get<double>(), 0.01 * std::abs(initial));
  EXPECT_DOUBLE_EQ(summary["energy"]["dissipated_by"]["contact"].get<double>(), rows.back().at("dissipated_contact"));
}

TEST(HeadlessRunner, TheNewtonLogHoldsEveryIterationAndAgreesWithTheStats) {
  // The drape at 10x10 started low, so that its steps go from free fall (one iteration) to
  // contact (several, some restricted to the Newton tail) within 12 frames.
  TempDir dir("weft_headless_newton_log");
  const std::vector<std::string> run = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                        "--quiet", "--newton-log", "--set", "cloths.0.grid.resolution=[10,10]",
                                        "--set", "cloths.0.transform.translation=[0,0.65,0]"};
  const fs::path out = dir.path() / "straight";
  std::vector<std::string> straight = run;
  straight.insert(straight.end(), {"--out", out.string(), "--frames", "12"});
  ASSERT_EQ(run_program(straight, dir.file("straight.txt")).exit_code, 0);
  const auto stats = read_stats(out / "stats.csv");
  const auto log = read_stats(out / "newton.csv");
  ASSERT_EQ(stats.size(), 13u);
  ASSERT_FALSE(log.empty());
  const double tolerance = 1e-2;  // the scene's solver.newton.tolerance
  std::map<int, double> newton, linear, worst;  // per frame, from the log
  int contact_iterations = 0;
  for (size_t k = 0; k < log.size(); ++k) {
    const auto& row = log[k];
    const int frame = static_cast<int>(row.at("frame"));
    ASSERT_GE(frame, 1);
    EXPECT_EQ(row.at("substep"), 0.0);
    EXPECT_EQ(row.at("cloth"), 0.0);
    // The residual is the largest of the vertices' shares: above the tolerance exactly when some
    // vertex is.
    EXPECT_EQ(row.at("residual") > tolerance, row.at("above_tolerance") > 0) << "row " << k + 1;
    if (row.at("iteration") == 0.0) {
      EXPECT_EQ(row.at("step_scale"), 0.0);
      EXPECT_EQ(row.at("linear_iterations"), 0.0);
    } else {
      // Iterations are numbered on from the step's start row.
      ASSERT_GT(k, 0u);
      EXPECT_EQ(row.at("iteration"), log[k - 1].at("iteration") + 1) << "row " << k + 1;
      EXPECT_EQ(row.at("step"), log[k - 1].at("step"));
      EXPECT_GT(row.at("step_scale"), 0.0);
      newton[frame] += 1.0 + row.at("restricted_iterations");
      linear[frame] += row.at("linear_iterations");
      if (row.at("iteration") > 1.0) ++contact_iterations;
    }
    const bool last_of_step = k + 1 == log.size() || log[k + 1].at("iteration") == 0.0;
    if (last_of_step) worst[frame] = std::max(worst[frame], row.at("residual"));
  }
  EXPECT_GT(contact_iterations, 0) << "the cloth reached the sphere";
  for (int frame = 1; frame <= 12; ++frame) {
    EXPECT_EQ(newton[frame], stats[frame].at("newton_iterations")) << "frame " << frame;
    EXPECT_EQ(linear[frame], stats[frame].at("linear_iterations")) << "frame " << frame;
    EXPECT_NEAR(worst[frame], stats[frame].at("newton_residual"), 1e-5 * stats[frame].at("newton_residual"))
        << "frame " << frame;
  }

  // Ended after frame 7 and resumed from its checkpoint at frame 6 (the log's frame 7 cut off and
  // written again): the same log as the straight run, byte for byte.
  const fs::path resumed = dir.path() / "resumed";
  std::vector<std::string> first = run;
  first.insert(first.end(), {"--out", resumed.string(), "--frames", "7", "--checkpoint-every", "6"});
  ASSERT_EQ(run_program(first, dir.file("first.txt")).exit_code, 0);
  std::vector<std::string> rest = run;
  rest.insert(rest.end(), {"--resume", resumed.string(), "--frames", "12"});
  ASSERT_EQ(run_program(rest, dir.file("rest.txt")).exit_code, 0);
  EXPECT_EQ(testing::read_bytes(resumed / "newton.csv"), testing::read_bytes(out / "newton.csv"));

  // Without the flag there is no log.
  const fs::path plain = dir.path() / "plain";
  const std::vector<std::string> without = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                            "--quiet", "--frames", "1", "--set", "cloths.0.grid.resolution=[6,6]",
                                            "--out", plain.string()};
  ASSERT_EQ(run_program(without, dir.file("plain.txt")).exit_code, 0);
  EXPECT_FALSE(fs::exists(plain / "newton.csv"));
  // A run stopped by a limit writes the iterations of the frame it stopped in, which has no
  // stats row: the falling drape passes 0.5 m/s in frame 2 (g t = 0.5 m/s at t = 0.051 s).
  const fs::path stopped = dir.path() / "stopped";
  const std::vector<std::string> limited = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                            "--quiet", "--newton-log", "--max-speed", "0.5", "--set",
                                            "cloths.0.grid.resolution=[6,6]", "--out", stopped.string()};
  ASSERT_EQ(run_program(limited, dir.file("stopped.txt")).exit_code, 3);
  const auto stopped_stats = read_stats(stopped / "stats.csv");
  const auto stopped_log = read_stats(stopped / "newton.csv");
  ASSERT_FALSE(stopped_log.empty());
  EXPECT_EQ(stopped_log.back().at("frame"), stopped_stats.back().at("frame") + 1);
  // The viewer records nothing: the flag is refused there, before any window opens.
  const auto viewer = run_program({weft_program, source_dir + "/scenes/drape_sphere.json", "--newton-log"},
                                  dir.file("viewer.txt"));
  EXPECT_EQ(viewer.exit_code, 2);
  EXPECT_NE(viewer.error_text.find("--newton-log needs --headless"), std::string::npos) << viewer.error_text;
}

TEST(HeadlessRunner, RefusesTheViewersOptions) {
  TempDir dir("weft_headless_viewer_options");
  const std::vector<std::vector<std::string>> options = {{"--play"},
                                                         {"--quit-after", "2"},
                                                         {"--frame-times", (dir.path() / "t.csv").string()},
                                                         {"--screenshot", (dir.path() / "s.png").string()}};
  for (const std::vector<std::string>& option : options) {
    std::vector<std::string> command = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                        "--quiet",    "--out",      (dir.path() / "out").string()};
    command.insert(command.end(), option.begin(), option.end());
    const auto run = run_program(command, dir.file("run.txt"));
    EXPECT_EQ(run.exit_code, 2) << option[0];
    EXPECT_NE(run.error_text.find(option[0] + " needs the viewer"), std::string::npos) << run.error_text;
    EXPECT_FALSE(fs::exists(dir.path() / "out")) << option[0] << ": nothing is recorded";
  }
}

TEST(HeadlessRunner, TheThreadsColumnShowsTheThreadsTheStepsRanOn) {
  // Frame 0 ran no step (0); with the governor off every step runs on the requested count.
  TempDir dir("weft_headless_threads");
  for (const int threads : {1, 2}) {
    const fs::path out = dir.path() / ("threads_" + std::to_string(threads));
    std::vector<std::string> run = {weft_program, "--headless", source_dir + "/scenes/drape_sphere.json",
                                    "--quiet"};
    run.insert(run.end(), {"--frames", "2", "--threads", std::to_string(threads), "--fixed-threads"});
    run.insert(run.end(), {"--set", "cloths.0.grid.resolution=[8,8]", "--out", out.string()});
    ASSERT_EQ(run_program(run, dir.file("run.txt")).exit_code, 0);
    const auto rows = read_stats(out / "stats.csv");
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[0].at("threads"), 0.0);
    EXPECT_EQ(rows[1].at("threads"), threads);
    EXPECT_EQ(rows[2].at("threads"), threads);
  }
}

TEST(HeadlessRunner, PinsHeldBackFromTheirScriptAreCountedAndWarnedOf) {
  // A small sheet with every vertex on a script is driven down at 2 m/s onto a sheet pinned
  // everywhere but at its centre vertex. Once that vertex is stopped, nothing of finite mass is
  // left to move, so the collision response's last resort holds the moving pins at their start
  // (collision/impact_zones.hpp): stats.csv's held_pins counts them in the frames where that
  // happened, such frames are not clean, summary.json has the total and the run warns. A plain
  // drape holds nothing. Untangling is off: on, it moves the free centre vertex once a step
  // ends unclean, and the punch then passes without a pin being held.
  TempDir dir("weft_headless_held_pins");
  // Every vertex of the sheet is pinned but its centre, 40 (tests/data/pinned_punch.json).
  const std::string scene = source_dir + "/tests/data/pinned_punch.json";
  const fs::path out = dir.path() / "punch";
  const testing::ProgramResult run = run_program(
      {weft_program, "--headless", scene, "--quiet", "--out", out.string(), "--set", "collision.untangle=false"},
      dir.file("punch.txt"));
  ASSERT_EQ(run.exit_code, 0) << run.error_text;
  const auto rows = read_stats(out / "stats.csv");
  ASSERT_EQ(rows.size(), 4u);
  int held = 0;
  double correction_max = 0.0;  // the punched pin drives cloth into cloth: the phase moves it
  for (const auto& row : rows) {
    ASSERT_EQ(row.count("held_pins"), 1u);
    correction_max = std::max(correction_max, row.at("collision_correction_max"));
    EXPECT_EQ(row.at("edges_over_strain_limit"), 0.0) << "no strain limit is set";
    held += static_cast<int>(row.at("held_pins"));
    if (row.at("held_pins") > 0.0) {
      EXPECT_EQ(row.at("collisions_clean"), 0.0) << "frame " << row.at("frame");
    }
  }
  EXPECT_GT(held, 0);
  EXPECT_EQ(testing::read_json(out / "summary.json")["held_pins"].get<int>(), held);
  EXPECT_GT(correction_max, 0.0);
  EXPECT_EQ(testing::read_json(out / "summary.json")["collision_correction_max"].get<double>(), correction_max);
  EXPECT_NE(run.error_text.find("held_pins"), std::string::npos) << run.error_text;

  const fs::path drape = dir.path() / "drape";
  const testing::ProgramResult plain =
      run_program({weft_program, "--headless", source_dir + "/scenes/drape_sphere.json", "--quiet",
                   "--frames", "2", "--set", "cloths.0.grid.resolution=[8,8]", "--out", drape.string()},
                  dir.file("drape.txt"));
  ASSERT_EQ(plain.exit_code, 0) << plain.error_text;
  EXPECT_EQ(testing::read_json(drape / "summary.json")["held_pins"].get<int>(), 0);
  EXPECT_EQ(plain.error_text.find("held_pins"), std::string::npos) << plain.error_text;
}

TEST(HeadlessRunner, BadInputExitsWithCodeTwoAndWritesNothing) {
  TempDir dir("weft_bad_input");
  const std::string scene = dir.file("bad.json");
  std::ofstream(scene) << R"({"cloths": [{"grid": {"size": [1, 1]}, "colour": "red"}]})";
  const fs::path out = dir.path() / "out";
  auto result = run_program({weft_program, "--headless", scene, "--out", out.string()}, dir.file("log1.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("bad.json: /cloths/0/colour: unknown key"), std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));

  result = run_program({weft_program, "--headless", source_dir + "/scenes/default.json", "--out", out.string(),
                        "--set", "solver.time_step=-0.001"},
                       dir.file("log2.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("/solver/time_step: expected a number > 0, got -0.001"), std::string::npos)
      << result.error_text;

  result = run_program({weft_program, "--headless", dir.file("nowhere.json"), "--out", out.string()},
                       dir.file("log3.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("nowhere.json"), std::string::npos) << result.error_text;

  result = run_program({weft_program, "--headless", source_dir + "/scenes/default.json"}, dir.file("log4.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("--out"), std::string::npos) << result.error_text;

  result = run_program({weft_program, "--frames", "many"}, dir.file("log5.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
}

TEST(HeadlessRunner, UnwritableOutputIsAClearError) {
  TempDir dir("weft_unwritable");
  const std::string blocker = dir.file("a_file");
  std::ofstream(blocker) << "not a folder";
  const auto result = run_program({weft_program, "--headless", source_dir + "/scenes/default.json", "--out",
                                   blocker + "/out", "--frames", "2", "--quiet"},
                                  dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 4);
  EXPECT_NE(result.error_text.find("a_file/out"), std::string::npos) << result.error_text;
}

TEST(HeadlessRunner, DivergenceStopsWithCodeThreeNamingTheVertex) {
  TempDir dir("weft_diverge");
  const fs::path out = dir.path() / "out";
  const auto result = run_program({weft_program, "--headless", source_dir + "/scenes/default.json", "--out",
                                   out.string(), "--frames", "50", "--quiet", "--format", "obj", "--set",
                                   "cloths.0.springs.structural.stiffness=1e12", "--set", "solver.time_step=0.01"},
                                  dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 3) << result.error_text;
  EXPECT_NE(result.error_text.find("diverged in frame"), std::string::npos) << result.error_text;
  EXPECT_NE(result.error_text.find("vertex"), std::string::npos) << result.error_text;
  EXPECT_TRUE(read_back((out / "frame_0000.obj").string()).ok);
}

TEST(HeadlessRunner, OneWriterPerOutputFolder) {
  TempDir dir("weft_lock_run");
  const fs::path out = dir.path() / "out";
  const std::vector<std::string> command = {
      weft_program, "--headless", source_dir + "/scenes/default.json", "--out", out.string(),
      "--quiet",    "--set",      "cloths.0.grid.resolution=[8,8]"};
  std::vector<std::string> endless = command;
  endless.insert(endless.end(), {"--frames", "10000000"});
  const pid_t first = testing::start_program(endless, dir.file("first.txt"));
  ASSERT_GT(first, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / "stats.csv") && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::vector<std::string> short_run = command;
  short_run.insert(short_run.end(), {"--frames", "2"});
  auto result = run_program(short_run, dir.file("second.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(
      result.error_text.find("out: in use by another weft run (pid " + std::to_string(first) + " on host "),
      std::string::npos)
      << result.error_text;
  kill(first, SIGINT);
  EXPECT_EQ(testing::wait_program(first, dir.file("first.txt")).exit_code, 130);
  EXPECT_FALSE(fs::exists(out / ".weft.lock"));

  // A lock left by a process that died (here: one that has exited) is taken over, with a note.
  const pid_t gone = testing::start_program({"/bin/true"}, dir.file("true.txt"));
  testing::wait_program(gone, dir.file("true.txt"));
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  std::ofstream(out / ".weft.lock") << "host " << host << "\npid " << gone << "\nstart 0\n";
  result = run_program(short_run, dir.file("third.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_NE(result.error_text.find("took over the lock of pid " + std::to_string(gone) + " on host " + host +
                                   ", which is no longer running"),
            std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out / ".weft.lock"));
}

TEST(HeadlessRunner, InterruptLeavesEveryWrittenFrameIntact) {
  TempDir dir("weft_interrupt");
  const fs::path out = dir.path() / "out";
  const std::string log = dir.file("log.txt");
  const pid_t pid = testing::start_program({weft_program, "--headless", source_dir + "/scenes/default.json",
                                            "--out", out.string(), "--frames", "100000", "--format", "obj", "--set",
                                            "cloths.0.grid.resolution=[48,48]"},
                                           log);
  ASSERT_GT(pid, 0);
  // Wait until a few frames exist, then press Ctrl-C.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / "frame_000003.obj") && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGINT);
  const auto result = testing::wait_program(pid, log);
  EXPECT_EQ(result.exit_code, 130) << result.error_text;
  EXPECT_NE(result.error_text.find("interrupted"), std::string::npos) << result.error_text;

  std::ifstream run_file(out / "run.json");
  const auto run = nlohmann::json::parse(run_file);
  EXPECT_EQ(run["status"], "interrupted");
  const int written = run["frames_written"];
  EXPECT_GE(written, 4);
  int frames_on_disk = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    if (entry.path().extension() == ".obj") {
      ++frames_on_disk;
      const ObjCounts counts = read_back(entry.path().string());
      EXPECT_TRUE(counts.ok) << entry.path();
      EXPECT_EQ(counts.vertices, 48u * 48u) << entry.path();
    }
  }
  EXPECT_EQ(frames_on_disk, written);
  EXPECT_EQ(count_lines((out / "stats.csv").string()), 1 + written);
  EXPECT_FALSE(has_temporary_files(out));
}

}  // namespace
}  // namespace weft
