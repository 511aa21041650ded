// Child processes, started without a shell: each argument reaches the program exactly as given, so no
// file or scene name can turn into a command (a name like x';touch PWNED;'.json stays a name).
//
// A child never outlives drape: it is killed and reaped when its ChildProcess goes before it was waited
// for (any error, any exception), and the kernel kills it when drape dies however it dies, SIGKILL
// included (PR_SET_PDEATHSIG, set in the child before it runs the program).
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace drape {

// The program as execvp would find it: a name with a '/' as it is, otherwise the first executable
// file of that name in a $PATH directory. nullopt when there is none.
std::optional<std::string> findProgram(const std::string& program);

class ChildProcess {
 public:
  struct Options {
    bool stdin_pipe = false;  // stdin is a pipe written through stdinFd(); otherwise /dev/null
    bool quiet = false;       // stdout and stderr to /dev/null; otherwise drape's
  };
  // Starts argv[0] (searched on $PATH). A program that cannot be found or started makes wait() 127.
  // Call from the thread that waits for it: the death signal follows the thread that started it.
  ChildProcess(const std::vector<std::string>& argv, Options options);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The write end of the child's stdin (stdin_pipe), or -1.
  int stdinFd() const { return stdin_; }
  void closeStdin();
  // Closes stdin and waits: the exit status, 128 + the signal that ended it, or 127 when it could not be
  // started (as a shell would).
  int wait();
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int stdin_ = -1;
  int status_ = 127;
};

// Runs argv and waits for it: ChildProcess(argv, {.quiet = quiet}).wait().
int runProcess(const std::vector<std::string>& argv, bool quiet = false);

}  // namespace drape
