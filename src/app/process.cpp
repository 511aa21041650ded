#include "app/process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>

extern char** environ;

namespace drape {

namespace {

bool isExecutableFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

int statusOf(int raw) {
  if (WIFEXITED(raw)) return WEXITSTATUS(raw);
  return WIFSIGNALED(raw) ? 128 + WTERMSIG(raw) : 127;
}

// In the child, between fork and exec: only async-signal-safe calls (the parent may have other threads,
// whose locks the child inherits held). Never returns.
[[noreturn]] void becomeProgram(const char* path, char* const* argv, pid_t parent, int stdin_read, bool quiet) {
  // SIGKILL when drape dies; if drape died before this line, nothing would send it: check.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(127);
  // An ignored SIGPIPE would be inherited through exec (drape ignores it while it feeds a pipe).
  ::signal(SIGPIPE, SIG_DFL);
  const int null_in = stdin_read >= 0 ? stdin_read : ::open("/dev/null", O_RDONLY);
  if (null_in < 0 || ::dup2(null_in, STDIN_FILENO) < 0) ::_exit(127);
  if (quiet) {
    const int null_out = ::open("/dev/null", O_WRONLY);
    if (null_out < 0 || ::dup2(null_out, STDOUT_FILENO) < 0 || ::dup2(null_out, STDERR_FILENO) < 0) ::_exit(127);
  }
  ::execve(path, argv, environ);
  ::_exit(127);
}

}  // namespace

std::optional<std::string> findProgram(const std::string& program) {
  if (program.empty()) return std::nullopt;
  if (program.find('/') != std::string::npos)
    return isExecutableFile(program) ? std::optional<std::string>(program) : std::nullopt;
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  for (std::size_t begin = 0; begin <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', begin), dirs.size());
    // An empty entry means the current directory, as for execvp.
    const std::string dir = end > begin ? dirs.substr(begin, end - begin) : ".";
    const std::string candidate = dir + "/" + program;
    if (isExecutableFile(candidate)) return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, Options options) {
  if (argv.empty()) return;
  const std::optional<std::string> path = findProgram(argv[0]);
  if (!path) return;
  // Everything the child needs is made before the fork: it must not allocate.
  std::vector<char*> args;
  for (const std::string& arg : argv)
    args.push_back(const_cast<char*>(arg.c_str()));  // execve does not write to them
  args.push_back(nullptr);
  int ends[2] = {-1, -1};
  // O_CLOEXEC: no other child inherits the write end, or the reader would never see the end of its input.
  if (options.stdin_pipe && ::pipe2(ends, O_CLOEXEC) != 0) return;
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ == 0) becomeProgram(path->c_str(), args.data(), parent, ends[0], options.quiet);
  if (ends[0] >= 0) ::close(ends[0]);
  if (pid_ < 0) {
    if (ends[1] >= 0) ::close(ends[1]);
    return;
  }
  stdin_ = ends[1];
}

ChildProcess::~ChildProcess() {
  closeStdin();
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    wait();
  }
}

void ChildProcess::closeStdin() {
  if (stdin_ >= 0) ::close(stdin_);
  stdin_ = -1;
}

int ChildProcess::wait() {
  closeStdin();
  if (pid_ <= 0) return status_;
  int raw = 0;
  pid_t got;
  while ((got = ::waitpid(pid_, &raw, 0)) < 0 && errno == EINTR) {
  }
  status_ = got == pid_ ? statusOf(raw) : 127;
  pid_ = -1;
  return status_;
}

int runProcess(const std::vector<std::string>& argv, bool quiet) {
  ChildProcess child(argv, {.quiet = quiet});
  return child.wait();
}

}  // namespace drape
