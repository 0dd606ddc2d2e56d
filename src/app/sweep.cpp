#include "app/sweep.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/sweep_status.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/output_lock.hpp"
#include "io/scene_file.hpp"
#include "io/sweep_file.hpp"

extern char** environ;

namespace weft {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t sweep_stop_requested = 0;
extern "C" void request_sweep_stop(int) { sweep_stop_requested = 1; }

// This program's own path, so cases run the same weft.
std::string own_executable() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string("weft") : self.string();
}

std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The options every case's weft command shares (after the scene and --out/--resume).
std::vector<std::string> common_arguments(const SweepDesc& sweep) {
  std::vector<std::string> arguments = {"--quiet", "--threads", std::to_string(sweep.threads), "--format",
                                        sweep.format};
  if (sweep.frames >= 0) {
    arguments.push_back("--frames");
    arguments.push_back(std::to_string(sweep.frames));
  }
  if (sweep.checkpoint_every > 0) {
    arguments.push_back("--checkpoint-every");
    arguments.push_back(std::to_string(sweep.checkpoint_every));
  }
  return arguments;
}

std::vector<std::string> override_arguments(const SweepCase& sweep_case) {
  std::vector<std::string> arguments;
  for (const std::string& assignment : sweep_case.overrides) {
    arguments.push_back("--set");
    arguments.push_back(assignment);
  }
  return arguments;
}

std::string slurm_script(const SweepDesc& sweep, const std::vector<SweepCase>& cases, const fs::path& out,
                         const std::string& weft) {
  const int last = static_cast<int>(cases.size()) - 1;
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Weft sweep \"" << sweep.name << "\": " << cases.size() << " cases of " << sweep.scene
    << ", one per array index.\n"
    << "# Written by `weft sweep --slurm " << sweep.source_file << "`.\n"
    << "#   submit:             sbatch " << (out / (sweep.name + ".sbatch")).string() << "\n"
    << "#   one case, locally:  SLURM_ARRAY_TASK_ID=0 bash " << (out / (sweep.name + ".sbatch")).string()
    << "\n"
    << "# A case already complete is skipped; one with a checkpoint resumes from it (requeue, preemption).\n"
    << "#SBATCH --job-name=weft-" << sweep.name << "\n"
    << "#SBATCH --array=0-" << last;
  if (sweep.slurm.max_parallel > 0) s << '%' << sweep.slurm.max_parallel;
  s << "\n#SBATCH --cpus-per-task=" << sweep.threads << "\n"
    << "#SBATCH --time=" << sweep.slurm.time << "\n"
    << "#SBATCH --mem=" << sweep.slurm.memory << "\n"
    << "#SBATCH --output=" << (out / "logs" / "%A_%a.log").string() << "\n"
    << "#SBATCH --open-mode=append\n"
    << "#SBATCH --requeue\n"
    << "#SBATCH --signal=B:TERM@120\n";
  if (!sweep.slurm.partition.empty()) s << "#SBATCH --partition=" << sweep.slurm.partition << "\n";
  for (const std::string& option : sweep.slurm.sbatch) s << "#SBATCH " << option << "\n";
  s << "set -euo pipefail\n\n"
    << "weft=${WEFT:-" << shell_quote(weft) << "}\n"
    << "scene=" << shell_quote(fs::absolute(sweep.scene).lexically_normal().string()) << "\n"
    << "sweep_dir=" << shell_quote(out.string()) << "\n"
    << "task=${SLURM_ARRAY_TASK_ID:?set SLURM_ARRAY_TASK_ID to a case index, 0.." << last << "}\n\n"
    << "case \"$task\" in\n";
  for (size_t i = 0; i < cases.size(); ++i) {
    s << "  " << i << ") name=" << shell_quote(cases[i].name) << "; overrides=(";
    const std::vector<std::string> arguments = override_arguments(cases[i]);
    for (size_t a = 0; a < arguments.size(); ++a) s << (a ? " " : "") << shell_quote(arguments[a]);
    s << ") ;;\n";
  }
  s << "  *) echo \"weft sweep: no case $task (cases are 0.." << last << ")\" >&2; exit 2 ;;\n"
    << "esac\n\n"
    << "out=\"$sweep_dir/$name\"\n"
    << "common=(";
  const std::vector<std::string> common = common_arguments(sweep);
  for (size_t a = 0; a < common.size(); ++a) s << (a ? " " : "") << shell_quote(common[a]);
  s << ")\n"
    << "restart=${SLURM_RESTART_COUNT:+, restart $SLURM_RESTART_COUNT}\n"
    << "echo \"weft sweep: case $task: $name on $(hostname)$restart\" >&2\n"
    << "if [[ -f \"$out/run.json\" ]] && grep -q '\"status\": \"complete\"' \"$out/run.json\"; then\n"
    << "  echo \"weft sweep: case $name is already complete\" >&2\n"
    << "  exit 0\n"
    << "fi\n"
    << "frames_written() {\n"
    << "  sed -n 's/^  \"frames_written\": \\([0-9]*\\),$/\\1/p' \"$out/run.json\" 2>/dev/null || true\n"
    << "}\n"
    << "frames_before=$(frames_written)\n\n"
    << "# weft runs as a child of this shell, which SLURM's warning before the time limit\n"
    << "# (--signal=B:TERM@...) reaches: passed on, weft ends its frame, checkpoints and exits 130.\n"
    << "stopping=0\n"
    << "stop() { stopping=1; kill -TERM \"${weft_pid:-}\" 2>/dev/null || true; }\n"
    << "trap stop TERM INT\n"
    << "if [[ -f \"$out/checkpoint.bin\" ]]; then\n"
    << "  \"$weft\" --headless \"$scene\" --resume \"$out\" \"${common[@]}\" \"${overrides[@]}\" &\n"
    << "else\n"
    << "  \"$weft\" --headless \"$scene\" --out \"$out\" \"${common[@]}\" \"${overrides[@]}\" &\n"
    << "fi\n"
    << "weft_pid=$!\n"
    << "while :; do\n"
    << "  stopping=0\n"
    << "  wait \"$weft_pid\" && code=0 || code=$?\n"
    << "  # A trapped signal ends `wait` early; wait again for weft's own exit.\n"
    << "  if (( stopping && code > 128 )) && kill -0 \"$weft_pid\" 2>/dev/null; then continue; fi\n"
    << "  break\n"
    << "done\n\n"
    << "# Interrupted with a checkpoint and further than it started: back in the queue to go on from it.\n"
    << "if (( code == 130 )) && [[ -n \"${SLURM_ARRAY_JOB_ID:-}\" && -f \"$out/checkpoint.bin\" ]]; then\n"
    << "  frames_after=$(frames_written)\n"
    << "  if (( ${frames_after:-0} > ${frames_before:-0} )); then\n"
    << "    echo \"weft sweep: case $name stopped after frame $(( frames_after - 1 )) with a checkpoint;\" "
       "\\\n"
    << "      \"requeueing ${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\" >&2\n"
    << "    scontrol requeue \"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\" ||\n"
    << "      echo \"weft sweep: the requeue failed; submit the case again: sbatch --array=$task \""
    << shell_quote((out / (sweep.name + ".sbatch")).string()) << " >&2\n"
    << "  else\n"
    << "    echo \"weft sweep: case $name made no progress in this job; not requeued\" \\\n"
    << "      \"(raise slurm.time)\" >&2\n"
    << "  fi\n"
    << "fi\n"
    << "exit \"$code\"\n";
  return s.str();
}

// The weft command line of one case run locally (resuming from a checkpoint if there is one).
std::vector<std::string> case_command(const SweepDesc& sweep, const SweepCase& sweep_case,
                                      const fs::path& case_dir, const std::string& weft, bool resume) {
  std::vector<std::string> command = {weft, "--headless", sweep.scene, resume ? "--resume" : "--out",
                                      case_dir.string()};
  for (const std::string& argument : common_arguments(sweep)) command.push_back(argument);
  for (const std::string& argument : override_arguments(sweep_case)) command.push_back(argument);
  return command;
}

pid_t spawn(const std::vector<std::string>& command, const std::string& log_file) {
  std::vector<char*> argv;
  for (const std::string& argument : command) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

std::string describe_exit(int code) {
  switch (code) {
    case 0:
      return "complete";
    case 2:
      return "bad input (exit 2)";
    case 3:
      return "diverged (exit 3)";
    case 4:
      return "output error (exit 4)";
    case 130:
      return "interrupted (exit 130)";
    default:
      return "failed (exit " + std::to_string(code) + ")";
  }
}

int run_locally(const SweepDesc& sweep, const std::vector<SweepCase>& cases,
                const std::vector<nlohmann::json>& case_scenes, const fs::path& out, int jobs) {
  const std::string weft = own_executable();
  struct Running {
    size_t index;
    std::chrono::steady_clock::time_point start;
    bool resumed;
  };
  std::map<pid_t, Running> running;
  size_t next = 0, finished = 0;
  bool stop_forwarded = false;
  std::vector<std::string> failed;
  const size_t total = cases.size();

  sweep_stop_requested = 0;
  struct sigaction action {};
  action.sa_handler = request_sweep_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);

  std::fprintf(stderr, "weft sweep: %zu cases of %s, %d at a time, into %s\n", total, sweep.scene.c_str(),
               jobs, out.c_str());
  while (finished < total) {
    // Start cases while there is a free worker.
    while (!sweep_stop_requested && next < total && static_cast<int>(running.size()) < jobs) {
      const SweepCase& sweep_case = cases[next];
      const fs::path case_dir = out / sweep_case.name;
      const CaseStatus status = case_status(case_dir, case_scenes[next], sweep.format);
      if (status.state == CaseState::complete) {
        ++finished;
        std::fprintf(stderr, "weft sweep: [%zu/%zu] %s already complete\n", finished, total,
                     sweep_case.name.c_str());
        ++next;
        continue;
      }
      // A case whose definition changed since it ran starts again (its checkpoint is of the old
      // one), as does one that already went past fewer frames now asked for, and one said
      // complete whose files are not.
      const RecordedCase recorded = recorded_case(case_dir, case_scenes[next], sweep.format);
      const int frames = case_scenes[next].value("frames", 0);
      const bool past_the_end = recorded.frames_changed && recorded.frames_written - 1 > frames;
      const bool checkpoint = fs::exists(case_dir / "checkpoint.bin");
      const bool unchanged = recorded.change.empty() && !recorded.frames_changed;
      const bool damaged = recorded.status == "complete" && unchanged;
      const bool again = !recorded.status.empty() && (!recorded.change.empty() || past_the_end ||
                                                      (recorded.frames_changed && !checkpoint) || damaged);
      if (damaged) {
        std::fprintf(stderr, "weft sweep: %s %s; running it again\n", sweep_case.name.c_str(),
                     status.detail.substr(0, status.detail.find("; the next sweep")).c_str());
      } else if (again) {
        std::fprintf(stderr, "weft sweep: %s changed since it ran (%s); running it again\n",
                     sweep_case.name.c_str(),
                     recorded.change.empty() ? "the scene differs at /frames" : recorded.change.c_str());
      }
      std::error_code error;
      fs::create_directories(case_dir, error);
      const bool resume = !again && checkpoint;
      const pid_t pid =
          spawn(case_command(sweep, sweep_case, case_dir, weft, resume), (case_dir / "log.txt").string());
      if (pid <= 0) {
        std::fprintf(stderr, "weft sweep: cannot start %s\n", weft.c_str());
        return 4;
      }
      running[pid] = {next, std::chrono::steady_clock::now(), resume};
      ++next;
    }
    if (running.empty()) break;  // interrupted before every case started
    // A stop (Ctrl-C reaches the cases too; SIGTERM to this process alone does not) is passed on
    // once, so every case ends after its current frame and writes its checkpoint.
    if (sweep_stop_requested && !stop_forwarded) {
      for (const auto& [case_pid, ignored] : running) kill(case_pid, SIGTERM);
      stop_forwarded = true;
    }
    int wait_status = 0;
    const pid_t pid = waitpid(-1, &wait_status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const SweepCase& sweep_case = cases[it->second.index];
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.start).count();
    const int code = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : 128 + WTERMSIG(wait_status);
    const bool resumed = it->second.resumed;
    running.erase(it);
    std::fprintf(stderr, "weft sweep: [%zu/%zu] %s %s in %.1f s%s%s\n", finished + 1, total,
                 sweep_case.name.c_str(), describe_exit(code).c_str(), seconds,
                 resumed ? " (resumed from its checkpoint)" : "",
                 code == 0 ? "" : (", see " + (out / sweep_case.name / "log.txt").string()).c_str());
    ++finished;
    if (code != 0) failed.push_back(sweep_case.name);
  }
  if (sweep_stop_requested) {
    std::fprintf(stderr,
                 "weft sweep: interrupted; run the same command again to finish (complete cases are kept, "
                 "checkpointed ones resume)\n");
    return 130;
  }
  if (!failed.empty()) {
    std::fprintf(stderr, "weft sweep: %zu of %zu cases failed:", failed.size(), total);
    for (const std::string& name : failed) std::fprintf(stderr, " %s", name.c_str());
    std::fprintf(stderr, "\n");
    return 5;
  }
  std::fprintf(stderr, "weft sweep: all %zu cases complete; recordings in %s\n", total, out.c_str());
  return 0;
}

}  // namespace

int run_sweep(const SweepOptions& options) {
  SweepDesc sweep;
  std::vector<SweepCase> cases;
  std::vector<nlohmann::json> case_scenes;  // each case's resolved scene, as its run.json will have it
  try {
    sweep = load_sweep_file(options.sweep_file);
    cases = expand_sweep(sweep);
    // Every case's scene must load before anything runs.
    for (const SweepCase& sweep_case : cases) {
      try {
        std::vector<std::string> overrides = sweep_case.overrides;
        if (sweep.frames >= 0) overrides.push_back("frames=" + std::to_string(sweep.frames));
        case_scenes.push_back(scene_to_json(load_scene_file(sweep.scene, overrides)));
      } catch (const SceneError& error) {
        throw SceneError(options.sweep_file, "/grid", "case " + sweep_case.name + ": " + error.what());
      }
    }
  } catch (const SceneError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 2;
  }
  if (!options.out_dir.empty()) sweep.out = options.out_dir;
  const fs::path out = fs::absolute(sweep.out).lexically_normal();
  if (options.dry_run) {
    for (const SweepCase& sweep_case : cases) std::printf("%s\n", sweep_case.name.c_str());
    return 0;
  }
  // Read only, without the sweep's lock: it answers while the sweep (or a SLURM array) runs.
  if (options.status) return print_sweep_status(sweep, cases, case_scenes, out);

  // One sweep per folder at a time (each case's run also locks its own folder); held until return.
  OutputLock lock;
  try {
    std::error_code error;
    fs::create_directories(out / "logs", error);
    if (error) throw IoError(out.string() + ": cannot create the sweep folder: " + error.message());
    lock = OutputLock(out);
    if (!lock.took_over().empty()) std::fprintf(stderr, "weft sweep: %s\n", lock.took_over().c_str());
    // The manifest: which case is which.
    nlohmann::json manifest = {{"name", sweep.name},
                               {"sweep_file", options.sweep_file},
                               {"scene", fs::absolute(sweep.scene).lexically_normal().string()},
                               {"cases", nlohmann::json::array()}};
    for (size_t i = 0; i < cases.size(); ++i) {
      manifest["cases"].push_back({{"index", i}, {"name", cases[i].name}, {"overrides", cases[i].overrides}});
    }
    write_file_atomically((out / "sweep.json").string(),
                          [&](std::ostream& stream) { stream << manifest.dump(2) << '\n'; });

    if (options.slurm) {
      const fs::path script = out / (sweep.name + ".sbatch");
      const std::string text = slurm_script(sweep, cases, out, own_executable());
      write_file_atomically(script.string(), [&](std::ostream& stream) { stream << text; });
      ::chmod(script.c_str(), 0755);
      std::printf("%s\n", script.c_str());
      std::fprintf(stderr, "weft sweep: wrote %s (%zu cases); submit it with: sbatch %s\n", script.c_str(),
                   cases.size(), script.c_str());
      return 0;
    }
  } catch (const OutputLocked& error) {
    std::fprintf(stderr, "weft sweep: %s\n", error.what());
    return 2;
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft: %s\n", error.what());
    return 4;
  }
  int jobs = options.jobs >= 0 ? options.jobs : sweep.jobs;
  if (jobs <= 0) jobs = std::max(1, static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN)) / sweep.threads);
  return run_locally(sweep, cases, case_scenes, out, jobs);
}

}  // namespace weft
