// The output folder's lock: one holder at a time, released on scope exit, a dead holder's lock
// on this host taken over, another host's never.
#include "io/output_lock.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

#include "support/files.hpp"
#include "support/temp_dir.hpp"

namespace weft {
namespace {

namespace fs = std::filesystem;
using testing::read_bytes;
using testing::TempDir;

// A pid that ran on this host and has ended (a child that exited and was reaped).
long dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

void write_lock(const fs::path& dir, const std::string& host, long pid) {
  std::ofstream(dir / output_lock_file) << "host " << host << "\npid " << pid << "\nstart 0\n";
}

TEST(OutputLock, HeldUntilScopeEndWithHostAndPid) {
  TempDir dir("weft_lock");
  {
    const OutputLock lock(dir.path());
    EXPECT_TRUE(lock.held());
    EXPECT_TRUE(lock.took_over().empty());
    const LockHolder holder = parse_lock_holder(read_bytes(dir.path() / output_lock_file));
    EXPECT_EQ(holder.pid, static_cast<long>(::getpid()));
    EXPECT_EQ(holder.host, this_process().host);
    EXPECT_GT(holder.start_time, 0u);
  }
  EXPECT_FALSE(fs::exists(dir.path() / output_lock_file));
}

TEST(OutputLock, ASecondWriterIsRefusedNamingTheHolder) {
  TempDir dir("weft_lock_twice");
  // Written as another live process of this host would (the test's parent: alive, not us).
  write_lock(dir.path(), this_process().host, static_cast<long>(::getppid()));
  try {
    const OutputLock second(dir.path());
    FAIL() << "a held lock was taken";
  } catch (const OutputLocked& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("in use by another weft run (pid " + std::to_string(::getppid()) + " on host " +
                           this_process().host + ", still running)"),
              std::string::npos)
        << message;
    EXPECT_EQ(error.holder().pid, static_cast<long>(::getppid()));
  }
  EXPECT_TRUE(fs::exists(dir.path() / output_lock_file));  // left to its holder
}

TEST(OutputLock, OurOwnLockTwiceIsRefusedToo) {
  TempDir dir("weft_lock_self");
  const OutputLock first(dir.path());
  EXPECT_THROW(OutputLock second(dir.path()), OutputLocked);
  EXPECT_TRUE(first.held());
}

TEST(OutputLock, ADeadHoldersLockIsTakenOver) {
  TempDir dir("weft_lock_stale");
  const long pid = dead_pid();
  write_lock(dir.path(), this_process().host, pid);
  {
    const OutputLock lock(dir.path());
    EXPECT_NE(lock.took_over().find("took over the lock of pid " + std::to_string(pid)), std::string::npos)
        << lock.took_over();
    EXPECT_EQ(parse_lock_holder(read_bytes(dir.path() / output_lock_file)).pid,
              static_cast<long>(::getpid()));
  }
  EXPECT_FALSE(fs::exists(dir.path() / output_lock_file));
}

TEST(OutputLock, AReusedPidWithAnotherStartTimeIsStale) {
  TempDir dir("weft_lock_reused");
  // Our parent's pid, but a start time that is not its own: the process that wrote it is gone.
  std::ofstream(dir.path() / output_lock_file)
      << "host " << this_process().host << "\npid " << ::getppid() << "\nstart 1\n";
  const OutputLock lock(dir.path());
  EXPECT_FALSE(lock.took_over().empty());
}

TEST(OutputLock, AnotherHostsLockIsNeverTakenOver) {
  TempDir dir("weft_lock_remote");
  write_lock(dir.path(), "node-that-is-not-this-one", dead_pid());
  try {
    const OutputLock lock(dir.path());
    FAIL() << "another host's lock was taken";
  } catch (const OutputLocked& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("on host node-that-is-not-this-one"), std::string::npos) << message;
    EXPECT_NE(message.find("if it is gone, remove " + (dir.path() / output_lock_file).string()),
              std::string::npos)
        << message;
  }
}

TEST(OutputLock, MovedLockIsReleasedOnce) {
  TempDir dir("weft_lock_move");
  OutputLock outer;
  EXPECT_FALSE(outer.held());
  {
    OutputLock inner(dir.path());
    outer = std::move(inner);
    EXPECT_FALSE(inner.held());  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
  }
  EXPECT_TRUE(fs::exists(dir.path() / output_lock_file));
  outer.release();
  EXPECT_FALSE(fs::exists(dir.path() / output_lock_file));
}

TEST(OutputLock, AnUnwritableFolderIsAnIoError) {
  EXPECT_THROW(OutputLock lock(fs::path("/proc/no_such_folder")), std::runtime_error);
}

}  // namespace
}  // namespace weft
