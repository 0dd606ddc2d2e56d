// `weft sweep`: a 2 x 2 grid over drape_sphere runs locally on a bounded pool (one progress line
// per run), and as a SLURM array script that passes `bash -n` and runs its cases locally with
// SLURM_ARRAY_TASK_ID set, giving the same recordings.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

#include "support/files.hpp"
#include "support/run_program.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using namespace weft::testing;

const std::string weft_program = WEFT_EXECUTABLE;
const std::string source_dir = WEFT_SOURCE_DIR;

std::string write_sweep(const TempDir& dir) {
  const std::string path = dir.file("drape.json");
  std::ofstream(path) << R"({
    "scene": ")" << source_dir
                      << R"(/scenes/drape_sphere.json",
    "frames": 4,
    "set": ["cloths.0.grid.resolution=[8,8]"],
    "grid": {"cloths.0.springs.structural.stiffness": [300, 600],
             "cloths.0.mass_damping": [0.1, 0.4]},
    "slurm": {"time": "00:10:00", "max_parallel": 2, "sbatch": ["--account=cloth"]}
  })";
  return path;
}

const std::vector<std::string> case_names = {
    "000_stiffness-300_mass_damping-0.1", "001_stiffness-300_mass_damping-0.4",
    "002_stiffness-600_mass_damping-0.1", "003_stiffness-600_mass_damping-0.4"};

int count(const std::string& text, const std::string& piece) {
  int n = 0;
  for (size_t at = text.find(piece); at != std::string::npos; at = text.find(piece, at + 1)) ++n;
  return n;
}

TEST(Sweep, RunsEveryCaseLocallyWithAProgressLineEach) {
  TempDir dir("weft_sweep_local");
  const fs::path out = dir.path() / "sweep";
  const auto result = run_program(
      {weft_program, "sweep", write_sweep(dir), "--out", out.string(), "--jobs", "2"}, dir.file("log.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_EQ(count(result.error_text, " complete in "), 4) << result.error_text;
  EXPECT_NE(result.error_text.find("[4/4]"), std::string::npos) << result.error_text;
  for (const std::string& name : case_names) {
    const auto run = read_json(out / name / "run.json");
    EXPECT_EQ(run["status"], "complete") << name;
    EXPECT_EQ(run["scene"]["frames"], 4) << name;
    EXPECT_TRUE(fs::exists(out / name / "cloth.pc2")) << name;
  }
  EXPECT_EQ(read_json(out / "002_stiffness-600_mass_damping-0.1" /
                      "run.json")["scene"]["cloths"][0]["springs"]["structural"]["stiffness"],
            600.0);
  EXPECT_EQ(read_json(out / "sweep.json")["cases"].size(), 4u);
  // Different parameters, different motion.
  EXPECT_NE(read_bytes(out / case_names[0] / "cloth.pc2"), read_bytes(out / case_names[3] / "cloth.pc2"));

  // Again: complete cases are not run twice.
  const auto again =
      run_program({weft_program, "sweep", write_sweep(dir), "--out", out.string()}, dir.file("again.txt"));
  EXPECT_EQ(again.exit_code, 0) << again.error_text;
  EXPECT_EQ(count(again.error_text, "already complete"), 4) << again.error_text;

  const auto status = run_program(
      {weft_program, "sweep", write_sweep(dir), "--out", out.string(), "--status"}, dir.file("status.txt"));
  EXPECT_EQ(status.exit_code, 0) << status.error_text;
  EXPECT_EQ(count(status.error_text, "  complete (frames 0..4)\n"), 4) << status.error_text;
  EXPECT_NE(status.error_text.find("drape: 4 of 4 complete; in "), std::string::npos) << status.error_text;
}

TEST(Sweep, ACaseWhoseDefinitionChangedRunsAgain) {
  TempDir dir("weft_sweep_changed");
  const fs::path out = dir.path() / "sweep";
  const std::string sweep = write_sweep(dir);
  ASSERT_EQ(run_program({weft_program, "sweep", sweep, "--out", out.string()}, dir.file("a.txt")).exit_code,
            0);
  // Five frames instead of four: every case's recording is of another scene now.
  std::string text = read_bytes(sweep);
  text.replace(text.find("\"frames\": 4"), 11, "\"frames\": 5");
  std::ofstream(sweep) << text;
  const auto result = run_program({weft_program, "sweep", sweep, "--out", out.string()}, dir.file("b.txt"));
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_EQ(count(result.error_text, "changed since it ran (the scene differs at /frames); running it again"),
            4)
      << result.error_text;
  EXPECT_EQ(count(result.error_text, "already complete"), 0) << result.error_text;
  EXPECT_EQ(read_json(out / case_names[0] / "run.json")["scene"]["frames"], 5);
}

TEST(Sweep, OneSweepPerFolderAndOneWriterPerCase) {
  TempDir dir("weft_sweep_locked");
  const fs::path out = dir.path() / "sweep";
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  const std::string held_by_us =
      "host " + std::string(host) + "\npid " + std::to_string(getpid()) + "\nstart 0\n";
  // The sweep folder held by a live process (this test): the sweep is refused before any case runs.
  fs::create_directories(out);
  std::ofstream(out / ".weft.lock") << held_by_us;
  auto result =
      run_program({weft_program, "sweep", write_sweep(dir), "--out", out.string()}, dir.file("a.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("in use by another weft run (pid " + std::to_string(getpid())),
            std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out / case_names[0]));
  fs::remove(out / ".weft.lock");

  // One case folder held: that case fails, naming the holder in its log; the others complete.
  fs::create_directories(out / case_names[1]);
  std::ofstream(out / case_names[1] / ".weft.lock") << held_by_us;
  result = run_program({weft_program, "sweep", write_sweep(dir), "--out", out.string()}, dir.file("b.txt"));
  EXPECT_EQ(result.exit_code, 5);
  EXPECT_NE(result.error_text.find(case_names[1] + " bad input (exit 2)"), std::string::npos)
      << result.error_text;
  EXPECT_NE(read_bytes(out / case_names[1] / "log.txt").find("in use by another weft run"),
            std::string::npos);
  EXPECT_EQ(read_json(out / case_names[0] / "run.json")["status"], "complete");
  EXPECT_FALSE(fs::exists(out / ".weft.lock"));
}

TEST(Sweep, SlurmScriptPassesBashCheckAndRunsArrayCasesLocally) {
  TempDir dir("weft_sweep_slurm");
  const fs::path out = dir.path() / "sweep";
  const auto written = run_program(
      {weft_program, "sweep", write_sweep(dir), "--out", out.string(), "--slurm"}, dir.file("log.txt"));
  ASSERT_EQ(written.exit_code, 0) << written.error_text;
  const fs::path script = out / "drape.sbatch";
  ASSERT_TRUE(fs::exists(script));
  const std::string text = read_bytes(script);
  EXPECT_NE(text.find("#SBATCH --array=0-3%2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("#SBATCH --time=00:10:00\n"), std::string::npos) << text;
  EXPECT_NE(text.find("#SBATCH --account=cloth\n"), std::string::npos) << text;
  EXPECT_NE(text.find("'--checkpoint-every' '10'"), std::string::npos) << text;  // the default
  EXPECT_NE(text.find("#SBATCH --requeue\n"), std::string::npos) << text;
  EXPECT_NE(text.find("#SBATCH --signal=B:TERM@120\n"), std::string::npos) << text;
  EXPECT_TRUE(fs::is_directory(out / "logs"));
  // Nothing ran.
  EXPECT_FALSE(fs::exists(out / case_names[0]));

  EXPECT_EQ(run_program({"/bin/bash", "-n", script.string()}, dir.file("syntax.txt")).exit_code, 0);

  for (const int index : {1, 2}) {
    const auto result = run_program(
        {"/usr/bin/env", "SLURM_ARRAY_TASK_ID=" + std::to_string(index), "/bin/bash", script.string()},
        dir.file("case.txt"));
    ASSERT_EQ(result.exit_code, 0) << result.error_text;
    EXPECT_EQ(read_json(out / case_names[index] / "run.json")["status"], "complete");
  }
  EXPECT_FALSE(fs::exists(out / case_names[0]));

  // The array case records exactly what the local sweep records for the same case.
  const fs::path local = dir.path() / "local";
  ASSERT_EQ(run_program({weft_program, "sweep", write_sweep(dir), "--out", local.string()}, dir.file("l.txt"))
                .exit_code,
            0);
  EXPECT_EQ(read_bytes(out / case_names[2] / "cloth.pc2"), read_bytes(local / case_names[2] / "cloth.pc2"));

  // An index past the cases, or none, is an error.
  auto result =
      run_program({"/usr/bin/env", "SLURM_ARRAY_TASK_ID=7", "/bin/bash", script.string()}, dir.file("x.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("no case 7"), std::string::npos) << result.error_text;
  result = run_program({"/usr/bin/env", "-u", "SLURM_ARRAY_TASK_ID", "/bin/bash", script.string()},
                       dir.file("y.txt"));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.error_text.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << result.error_text;
}

// SLURM's warning before a time limit (--signal=B:TERM@120) goes to the array task's shell alone:
// the shell passes it on, weft stops after a whole frame with a checkpoint, and the task requeues
// itself (`scontrol requeue JOB_TASK`, here a stand-in that records its arguments). Run again, the
// task resumes from the checkpoint and says so.
TEST(Sweep, ArrayTaskStoppedBeforeItsTimeLimitRequeuesItselfAndResumes) {
  TempDir dir("weft_sweep_requeue");
  const std::string path = dir.file("long.json");
  const auto write_long = [&](int frames) {
    std::ofstream(path) << R"({"scene": ")" << source_dir << R"(/scenes/drape_sphere.json", "frames": )"
                        << frames << R"(, "set": ["cloths.0.grid.resolution=[6,6]"],
      "grid": {"cloths.0.mass_damping": [0.1]}})";
  };
  write_long(100000);
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(run_program({weft_program, "sweep", path, "--out", out.string(), "--slurm"}, dir.file("w.txt"))
                .exit_code,
            0);
  const fs::path bin = dir.path() / "bin";
  fs::create_directories(bin);
  std::ofstream(bin / "scontrol") << "#!/bin/sh\necho \"$@\" >> " << dir.file("scontrol.txt") << "\n";
  fs::permissions(bin / "scontrol", fs::perms::owner_all);
  const std::vector<std::string> task = {"/usr/bin/env",
                                         "PATH=" + bin.string() + ":/usr/bin:/bin",
                                         "SLURM_ARRAY_TASK_ID=0",
                                         "SLURM_ARRAY_JOB_ID=77",
                                         "/bin/bash",
                                         (out / "long.sbatch").string()};
  const fs::path case_dir = out / "000_mass_damping-0.1";
  const std::string log = dir.file("task.txt");
  const pid_t pid = start_program(task, log);
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (count_lines(case_dir / "stats.csv") < 25 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGTERM);  // to the shell only, as --signal=B: does
  const auto stopped = wait_program(pid, log);
  EXPECT_EQ(stopped.exit_code, 130) << stopped.error_text;
  const auto run = read_json(case_dir / "run.json");
  EXPECT_EQ(run["status"], "interrupted");
  const int frames_written = run["frames_written"];
  EXPECT_GE(frames_written, 24);
  EXPECT_TRUE(fs::exists(case_dir / "checkpoint.bin"));
  EXPECT_NE(stopped.error_text.find("stopped after frame " + std::to_string(frames_written - 1) +
                                    " with a checkpoint; requeueing 77_0"),
            std::string::npos)
      << stopped.error_text;
  EXPECT_EQ(read_bytes(dir.file("scontrol.txt")), "requeue 77_0\n");

  // The requeued task (a few frames further now, so that it ends) goes on from the checkpoint.
  write_long(frames_written + 2);
  ASSERT_EQ(run_program({weft_program, "sweep", path, "--out", out.string(), "--slurm"}, dir.file("w2.txt"))
                .exit_code,
            0);
  const auto resumed = run_program(task, dir.file("task2.txt"));
  EXPECT_EQ(resumed.exit_code, 0) << resumed.error_text;
  EXPECT_NE(resumed.error_text.find("weft: resumed from frame " + std::to_string(frames_written - 1) +
                                    " of " + std::to_string(frames_written + 2)),
            std::string::npos)
      << resumed.error_text;
  EXPECT_EQ(read_json(case_dir / "run.json")["status"], "complete");
  EXPECT_EQ(read_bytes(dir.file("scontrol.txt")), "requeue 77_0\n");  // not again
}

// SIGTERM to the sweep alone (a batch system stopping the job's main process) reaches the
// running cases: each stops after a whole frame with a checkpoint, and a second sweep resumes.
TEST(Sweep, StopIsPassedToRunningCasesWhichResumeOnTheNextSweep) {
  TempDir dir("weft_sweep_stop");
  const std::string path = dir.file("long.json");
  std::ofstream(path) << R"({"scene": ")" << source_dir << R"(/scenes/drape_sphere.json", "frames": 100000,
    "checkpoint_every": 1, "set": ["cloths.0.grid.resolution=[6,6]"],
    "grid": {"cloths.0.mass_damping": [0.1, 0.2]}})";
  const fs::path out = dir.path() / "out";
  const std::string log = dir.file("log.txt");
  const pid_t pid = start_program({weft_program, "sweep", path, "--out", out.string(), "--jobs", "2"}, log);
  ASSERT_GT(pid, 0);
  const std::vector<std::string> names = {"000_mass_damping-0.1", "001_mass_damping-0.2"};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!(fs::exists(out / names[0] / "checkpoint.bin") && fs::exists(out / names[1] / "checkpoint.bin")) &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(fs::exists(out / names[1] / "checkpoint.bin"));
  const auto running =
      run_program({weft_program, "sweep", path, "--out", out.string(), "--status"}, dir.file("running.txt"));
  EXPECT_EQ(running.exit_code, 1) << running.error_text;
  EXPECT_EQ(count(running.error_text, "  running on "), 2) << running.error_text;
  EXPECT_NE(running.error_text.find("long: 0 of 2 complete, 2 running;"), std::string::npos)
      << running.error_text;
  kill(pid, SIGTERM);
  const auto result = wait_program(pid, log);
  EXPECT_EQ(result.exit_code, 130) << result.error_text;
  for (const std::string& name : names) {
    EXPECT_EQ(read_json(out / name / "run.json")["status"], "interrupted") << name;
  }
  const auto stopped =
      run_program({weft_program, "sweep", path, "--out", out.string(), "--status"}, dir.file("stopped.txt"));
  EXPECT_EQ(stopped.exit_code, 1) << stopped.error_text;
  EXPECT_EQ(count(stopped.error_text, "  interrupted after frame "), 2) << stopped.error_text;
  EXPECT_EQ(count(stopped.error_text, "; resumable from its checkpoint at frame "), 2) << stopped.error_text;
  EXPECT_NE(stopped.error_text.find("long: 0 of 2 complete, 2 interrupted (2 resumable);"), std::string::npos)
      << stopped.error_text;
  EXPECT_NE(result.error_text.find("interrupted"), std::string::npos) << result.error_text;

  // The same sweep asking for a few frames more than were written: both cases resume from their
  // checkpoints (not from frame 0) and finish.
  int stopped_at = 0;
  for (const std::string& name : names) {
    stopped_at = std::max(stopped_at, read_json(out / name / "run.json")["frames_written"].get<int>());
  }
  const int frames = stopped_at + 3;
  std::ofstream(path) << R"({"scene": ")" << source_dir << R"(/scenes/drape_sphere.json", "frames": )"
                      << frames << R"(, "checkpoint_every": 1, "set": ["cloths.0.grid.resolution=[6,6]"],
    "grid": {"cloths.0.mass_damping": [0.1, 0.2]}})";
  const auto again = run_program({weft_program, "sweep", path, "--out", out.string()}, dir.file("again.txt"));
  ASSERT_EQ(again.exit_code, 0) << again.error_text;
  for (const std::string& name : names) {
    EXPECT_EQ(read_json(out / name / "run.json")["status"], "complete") << name;
    EXPECT_EQ(read_json(out / name / "summary.json")["frames_written"], frames + 1) << name;
  }
  EXPECT_EQ(count(again.error_text, "complete in"), 2) << again.error_text;
  EXPECT_EQ(count(again.error_text, "(resumed from its checkpoint)"), 2) << again.error_text;
  // Each case's own log says where it went on from.
  for (const std::string& name : names) {
    EXPECT_NE(read_bytes(out / name / "log.txt").find("weft: resumed from frame "), std::string::npos)
        << name;
  }
}

// `--status` reads each case from its files: a lock held by a live process is a running case, a
// run.json saying "complete" needs a recording and stats.csv with every frame, a run that stopped
// is resumable when it left a checkpoint. The next sweep runs what is not complete.
TEST(Sweep, StatusSaysWhereEachCaseStandsFromItsFiles) {
  TempDir dir("weft_sweep_status");
  const std::string path = dir.file("states.json");
  std::ofstream(path) << R"({"scene": ")" << source_dir << R"(/scenes/drape_sphere.json", "frames": 5,
    "checkpoint_every": 2, "set": ["cloths.0.grid.resolution=[6,6]"],
    "grid": {"cloths.0.mass_damping": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]}})";
  const fs::path out = dir.path() / "out";
  std::vector<std::string> names;
  for (int i = 0; i < 7; ++i)
    names.push_back("00" + std::to_string(i) + "_mass_damping-0." + std::to_string(i + 1));
  const auto status = [&](const std::string& log) {
    return run_program({weft_program, "sweep", path, "--out", out.string(), "--status"}, dir.file(log));
  };
  const auto line_of = [](const std::string& text, const std::string& name) {
    const size_t at = text.find(name + "  ");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  };

  auto result = status("before.txt");
  EXPECT_EQ(result.exit_code, 1) << result.error_text;
  EXPECT_EQ(count(result.error_text, "  not started\n"), 7) << result.error_text;
  EXPECT_NE(result.error_text.find("states: 0 of 7 complete, 7 not started; in "), std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));  // reading writes nothing

  ASSERT_EQ(run_program({weft_program, "sweep", path, "--out", out.string()}, dir.file("run.txt")).exit_code,
            0);
  const auto edit_run = [&](const std::string& name, const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json run = read_json(out / name / "run.json");
    change(run);
    std::ofstream(out / name / "run.json") << run.dump(2) << '\n';
  };
  // 0 complete. 1 running: its folder locked by this (live) process.
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  std::ofstream(out / names[1] / ".weft.lock") << "host " << host << "\npid " << getpid() << "\nstart 0\n";
  // 2 stopped after frame 4 with its checkpoint at frame 4 (every 2 frames).
  edit_run(names[2], [](nlohmann::json& run) {
    run["status"] = "interrupted";
    run["frames_written"] = 5;
  });
  {
    const std::string stats = read_bytes(out / names[2] / "stats.csv");
    std::ofstream(out / names[2] / "stats.csv") << stats.substr(0, stats.rfind('\n', stats.size() - 2) + 1);
  }
  // 3 killed (run.json still says running, no lock) without a checkpoint.
  edit_run(names[3], [](nlohmann::json& run) { run["status"] = "running"; });
  fs::remove(out / names[3] / "checkpoint.bin");
  // 4 says complete, but its point cache was cut to 3 frames.
  {
    std::string cache = read_bytes(out / names[4] / "cloth.pc2");
    const int samples = 3;
    std::memcpy(&cache[28], &samples, 4);
    std::ofstream(out / names[4] / "cloth.pc2", std::ios::binary) << cache;
  }
  // 5 diverged.
  edit_run(names[5], [](nlohmann::json& run) { run["status"] = "diverged"; });
  std::ofstream(out / names[5] / "summary.json")
      << R"({"status": "diverged", "failure": {"frame": 3, "message": "vertex 7 moves at 1e+09 m/s"}})";
  // 6 recorded with another scene.
  edit_run(names[6], [](nlohmann::json& run) { run["scene"]["fps"] = 17; });

  result = status("after.txt");
  const std::string& text = result.error_text;
  EXPECT_EQ(result.exit_code, 5) << text;
  EXPECT_EQ(line_of(text, names[0]), names[0] + "  complete (frames 0..5)") << text;
  const std::string running = line_of(text, names[1]);
  EXPECT_EQ(running.rfind(names[1] + "  running on " + host + ", pid " + std::to_string(getpid()) +
                              ": frame 5 of 5, written ",
                          0),
            0u)
      << text;
  EXPECT_EQ(running.substr(running.size() - 4), " ago") << text;
  EXPECT_EQ(line_of(text, names[2]),
            names[2] + "  interrupted after frame 4 of 5; resumable from its checkpoint at frame 4")
      << text;
  EXPECT_EQ(line_of(text, names[3]), names[3] +
                                         "  interrupted (killed) after frame 5 of 5; not resumable: no "
                                         "checkpoint, the next sweep starts it again")
      << text;
  EXPECT_EQ(line_of(text, names[4]),
            names[4] +
                "  failed run.json says complete, but cloth.pc2 holds 3 frames of 6; "
                "the next sweep runs it again")
      << text;
  EXPECT_EQ(line_of(text, names[5]), names[5] + "  failed diverged in frame 3: vertex 7 moves at 1e+09 m/s")
      << text;
  EXPECT_EQ(line_of(text, names[6]),
            names[6] + "  changed since it ran (the scene differs at /fps); the next sweep runs it again")
      << text;
  EXPECT_NE(
      text.find("states: 1 of 7 complete, 1 running, 2 interrupted (1 resumable), 2 failed, 1 changed; in "),
      std::string::npos)
      << text;

  // The lock released, the next sweep runs every case that is not complete, and then all are.
  fs::remove(out / names[1] / ".weft.lock");
  const auto again = run_program({weft_program, "sweep", path, "--out", out.string()}, dir.file("again.txt"));
  EXPECT_EQ(again.exit_code, 0) << again.error_text;
  EXPECT_NE(again.error_text.find(names[4] + " run.json says complete, but cloth.pc2 holds 3 frames of 6; "
                                             "running it again"),
            std::string::npos)
      << again.error_text;
  EXPECT_NE(again.error_text.find(names[2] + " complete in"), std::string::npos) << again.error_text;
  EXPECT_EQ(count(again.error_text, "already complete"), 2) << again.error_text;
  result = status("last.txt");
  EXPECT_EQ(result.exit_code, 0) << result.error_text;
  EXPECT_NE(result.error_text.find("states: 7 of 7 complete; in "), std::string::npos) << result.error_text;
  EXPECT_EQ(read_bytes(out / names[4] / "cloth.pc2").size(), read_bytes(out / names[0] / "cloth.pc2").size());
}

TEST(Sweep, BadSweepOrCaseIsRefusedBeforeAnythingRuns) {
  TempDir dir("weft_sweep_bad");
  const std::string path = dir.file("bad.json");
  std::ofstream(path) << R"({"scene": ")" << source_dir
                      << R"(/scenes/drape_sphere.json", "grid": {"solver.time_step": [0.002, -1]}})";
  const fs::path out = dir.path() / "out";
  auto result = run_program({weft_program, "sweep", path, "--out", out.string()}, dir.file("log.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("bad.json: /grid: case 001_time_step--1"), std::string::npos)
      << result.error_text;
  EXPECT_NE(result.error_text.find("/solver/time_step: expected a number > 0"), std::string::npos)
      << result.error_text;
  EXPECT_FALSE(fs::exists(out));

  result = run_program({weft_program, "sweep", dir.file("none.json")}, dir.file("log2.txt"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.error_text.find("none.json"), std::string::npos) << result.error_text;
}

}  // namespace
}  // namespace weft
