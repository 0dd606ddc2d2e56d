#include "io/output_lock.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.hpp"

namespace weft {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown-host";
  return name;
}

// Clock ticks from boot to the start of process `pid` (field 22 of /proc/PID/stat), 0 if unknown.
// With the pid it names one process: a pid reused after a crash has another start time.
unsigned long long process_start_time(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(in, text);
  const size_t name_end = text.rfind(')');  // the command name may hold spaces and parentheses
  if (name_end == std::string::npos) return 0;
  std::istringstream fields(text.substr(name_end + 1));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k) {
    if (k == 22) return std::strtoull(field.c_str(), nullptr, 10);
  }
  return 0;
}

std::string read_text(const fs::path& path, bool& found) {
  std::ifstream in(path);
  found = static_cast<bool>(in);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string lock_text(const LockHolder& holder) {
  return "host " + holder.host + "\npid " + std::to_string(holder.pid) + "\nstart " +
         std::to_string(holder.start_time) + "\n";
}

std::string describe(const LockHolder& holder) {
  return "pid " + std::to_string(holder.pid) + " on host " + holder.host;
}

// A lock file still empty or half written this long after its creation is taken for damaged.
constexpr auto unreadable_lock_age = std::chrono::seconds(2);

}  // namespace

LockHolder parse_lock_holder(const std::string& text) {
  LockHolder holder;
  std::istringstream lines(text);
  for (std::string key, value; lines >> key >> value;) {
    if (key == "host") holder.host = value;
    if (key == "pid") holder.pid = std::strtol(value.c_str(), nullptr, 10);
    if (key == "start") holder.start_time = std::strtoull(value.c_str(), nullptr, 10);
  }
  if (holder.host.empty() || holder.pid <= 0) holder.pid = 0;
  return holder;
}

LockHolder this_process() {
  const long pid = static_cast<long>(::getpid());
  return {host_name(), pid, process_start_time(pid)};
}

bool lock_holder_is_dead(const LockHolder& holder) {
  if (holder.pid <= 0 || holder.host != host_name()) return false;
  if (::kill(static_cast<pid_t>(holder.pid), 0) != 0 && errno == ESRCH) return true;
  const unsigned long long now = process_start_time(holder.pid);
  return holder.start_time != 0 && now != 0 && now != holder.start_time;
}

OutputLock::OutputLock(const fs::path& dir) {
  const fs::path path = dir / output_lock_file;
  const LockHolder self = this_process();
  const std::string text = lock_text(self);
  // A few rounds: a lock file may vanish, be half written or be taken over while we look at it.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
      ::close(fd);
      if (!written) {
        ::unlink(path.c_str());
        throw IoError(path.string() + ": cannot write the output folder's lock file");
      }
      path_ = path;
      contents_ = text;
      return;
    }
    if (errno != EEXIST) {
      throw IoError(path.string() + ": cannot create the output folder's lock file: " + std::strerror(errno));
    }

    bool found = false;
    const std::string held = read_text(path, found);
    if (!found) continue;  // released between our open and our read
    const LockHolder holder = parse_lock_holder(held);
    if (holder.pid == 0) {
      // Being written by the process that just created it, or left damaged: wait a little.
      std::error_code error;
      const auto written_at = fs::last_write_time(path, error);
      if (error || fs::file_time_type::clock::now() - written_at < unreadable_lock_age) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
    } else if (!lock_holder_is_dead(holder)) {
      const bool here = holder.host == self.host;
      throw OutputLocked(dir.string() + ": in use by another weft run (" + describe(holder) +
                             (here ? ", still running" : "") + "); wait for it to end or stop it" +
                             (here ? "" : "; if it is gone, remove " + path.string()),
                         holder);
    }

    // Stale: move it aside under a name of our own, and check that what moved is the stale lock
    // and not one another process created after taking it over first (then it goes back).
    const fs::path aside = path.string() + ".stale." + std::to_string(self.pid);
    if (::rename(path.c_str(), aside.c_str()) != 0) continue;
    bool moved = false;
    if (read_text(aside, moved) != held) {
      ::link(aside.c_str(), path.c_str());
      ::unlink(aside.c_str());
      continue;
    }
    ::unlink(aside.c_str());
    took_over_ = path.string() + ": took over the lock of " +
                 (holder.pid == 0 ? std::string("a writer that left it unreadable")
                                  : describe(holder) + ", which is no longer running");
  }
  throw IoError(path.string() + ": cannot take the output folder's lock (it keeps changing)");
}

OutputLock::~OutputLock() { release(); }

OutputLock::OutputLock(OutputLock&& other) noexcept
    : path_(std::move(other.path_)),
      contents_(std::move(other.contents_)),
      took_over_(std::move(other.took_over_)) {
  other.path_.clear();
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    path_ = std::move(other.path_);
    contents_ = std::move(other.contents_);
    took_over_ = std::move(other.took_over_);
    other.path_.clear();
  }
  return *this;
}

void OutputLock::release() {
  if (path_.empty()) return;
  // Only our own file: after a forced takeover (someone removed ours) it belongs to another run.
  bool found = false;
  if (read_text(path_, found) == contents_ && found) ::unlink(path_.c_str());
  path_.clear();
}

}  // namespace weft
