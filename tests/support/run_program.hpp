#pragma once
// Runs the weft program as a user would and collects its exit code and stderr.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace weft::testing {

struct ProgramResult {
  int exit_code = -1;      // exit status, or 128 + signal number if killed
  std::string error_text;  // everything written to stderr
};

// Whether `text` (a program's stderr, a file's contents) holds `piece`.
inline bool contains(const std::string& text, const std::string& piece) {
  return text.find(piece) != std::string::npos;
}

// Starts `arguments` (argv[0] is the program) with stdout and stderr to `log_file`; returns the pid.
inline pid_t start_program(const std::vector<std::string>& arguments, const std::string& log_file) {
  std::vector<char*> argv;
  for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

inline ProgramResult wait_program(pid_t pid, const std::string& log_file) {
  ProgramResult result;
  int status = 0;
  if (pid > 0 && waitpid(pid, &status, 0) == pid) {
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::ifstream log(log_file);
  std::stringstream text;
  text << log.rdbuf();
  result.error_text = text.str();
  return result;
}

inline ProgramResult run_program(const std::vector<std::string>& arguments, const std::string& log_file) {
  return wait_program(start_program(arguments, log_file), log_file);
}

// Waits until `path` exists, at most `limit`; returns whether it does.
inline bool wait_for(const std::filesystem::path& path, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!std::filesystem::exists(path)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return true;
}

}  // namespace weft::testing
