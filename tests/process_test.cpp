// Child processes never outlive drape: killed and reaped when their owner goes, killed by the kernel when
// drape itself is killed with SIGKILL.
#include "app/process.hpp"
#include "core/atomic_file.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace drape {
namespace {

namespace fs = std::filesystem;

// Gone, or a zombie nobody reaps yet (an orphan's reaper may be slow): either way it runs no more.
bool ended(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return true;
  const std::size_t paren = text.rfind(')');
  return paren != std::string::npos && paren + 2 < text.size() && (text[paren + 2] == 'Z' || text[paren + 2] == 'X');
}

bool endsWithin(pid_t pid, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!ended(pid)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

TEST(ChildProcess, ReportsExitStatusesSignalsAndMissingPrograms) {
  EXPECT_EQ(runProcess({"sh", "-c", "exit 3"}), 3);
  EXPECT_EQ(runProcess({"sh", "-c", "kill -9 $$"}), 128 + SIGKILL);
  EXPECT_EQ(runProcess({"drape-no-such-program"}), 127);
  EXPECT_EQ(runProcess({}), 127);
}

TEST(ChildProcess, FeedsItsStdinThroughAPipe) {
  const fs::path out = fs::temp_directory_path() / ("drape_process_stdin_" + std::to_string(::getpid()));
  ChildProcess cat({"sh", "-c", "cat > \"$0\"", out.string()}, {.stdin_pipe = true});
  ASSERT_GE(cat.stdinFd(), 0);
  ASSERT_TRUE(writeAll(cat.stdinFd(), "frames"));
  EXPECT_EQ(cat.wait(), 0);
  std::stringstream text;
  text << std::ifstream(out).rdbuf();
  EXPECT_EQ(text.str(), "frames");
  fs::remove(out);
}

// An error path: the owner goes without waiting (an exception); the child is killed and reaped.
TEST(ChildProcess, AChildWhoseOwnerGoesIsKilledAndReaped) {
  pid_t pid = -1;
  {
    const ChildProcess sleeper({"sleep", "60"}, {.stdin_pipe = true});
    pid = sleeper.pid();
    ASSERT_GT(pid, 0);
  }
  errno = 0;
  EXPECT_EQ(::kill(pid, 0), -1);
  EXPECT_EQ(errno, ESRCH) << "reaped, not left a zombie";
}

// kill -9 of the process that started it: no destructor runs, the kernel's death signal ends the child.
TEST(ChildProcess, AChildDiesWithItsParentKilledBySigkill) {
  int ends[2];
  ASSERT_EQ(::pipe(ends), 0);
  const pid_t parent = ::fork();
  ASSERT_GE(parent, 0);
  if (parent == 0) {
    const ChildProcess sleeper({"sleep", "60"}, {});
    const pid_t pid = sleeper.pid();
    if (::write(ends[1], &pid, sizeof pid) != sizeof pid) ::_exit(1);
    ::pause();
    ::_exit(0);
  }
  pid_t sleeper = -1;
  ASSERT_EQ(::read(ends[0], &sleeper, sizeof sleeper), ssize_t(sizeof sleeper));
  ::close(ends[0]);
  ::close(ends[1]);
  ASSERT_GT(sleeper, 0);
  EXPECT_FALSE(ended(sleeper));
  ::kill(parent, SIGKILL);
  ::waitpid(parent, nullptr, 0);
  EXPECT_TRUE(endsWithin(sleeper, std::chrono::seconds(10))) << "sleep " << sleeper << " outlived its parent";
  ::kill(sleeper, SIGKILL);  // should the test fail, nothing is left running
}

}  // namespace
}  // namespace drape
