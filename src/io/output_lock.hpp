#pragma once
// One writer per output folder: a run, a resumed run or a sweep holds DIR/.weft.lock (the
// holder's host, pid and process start time) while it writes there, and a second writer is
// refused with the holder named. The file is created with O_CREAT | O_EXCL, which is atomic on
// local disks and on NFS v3 and later, so it works across the nodes of a cluster.
//
// A lock left by a process that died (kill -9, a crash, a node reboot) is stale: on the same
// host, a pid that no longer runs, or runs a different process (another start time), is taken
// over with a note. A lock from another host cannot be checked and is never taken over; the
// error says which file to remove.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace weft {

constexpr const char* output_lock_file = ".weft.lock";

// Who holds a lock, as written in the lock file.
struct LockHolder {
  std::string host;
  long pid = 0;
  unsigned long long start_time = 0;  // clock ticks after boot (/proc/PID/stat), 0 if unknown
};

// The folder is locked by another live writer.
class OutputLocked : public std::runtime_error {
 public:
  OutputLocked(const std::string& message, LockHolder holder)
      : std::runtime_error(message), holder_(std::move(holder)) {}
  const LockHolder& holder() const { return holder_; }

 private:
  LockHolder holder_;
};

class OutputLock {
 public:
  OutputLock() = default;
  // Takes DIR/.weft.lock (DIR must exist). Throws OutputLocked when another live process holds
  // it, IoError when the file cannot be created.
  explicit OutputLock(const std::filesystem::path& dir);
  ~OutputLock();  // removes the lock file, if it is still this process's
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  bool held() const { return !path_.empty(); }
  // Non-empty when a stale lock was taken over: says whose it was.
  const std::string& took_over() const { return took_over_; }
  void release();

 private:
  std::filesystem::path path_;
  std::string contents_;  // what this process wrote, to recognise its own file on release
  std::string took_over_;
};

// The holder written in a lock file's text; pid 0 if unreadable.
LockHolder parse_lock_holder(const std::string& text);
// This process as a lock holder.
LockHolder this_process();
// True when `holder` ran on this host and its process is gone (or the pid now runs another program).
bool lock_holder_is_dead(const LockHolder& holder);

}  // namespace weft
