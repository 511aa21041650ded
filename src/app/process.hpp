// Child processes, started without a shell: each argument reaches the program exactly as given, so no
// file or scene name can turn into a command (a name like x';touch PWNED;'.json stays a name).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace drape {

// The program as execvp would find it: a name with a '/' as it is, otherwise the first executable
// file of that name in a $PATH directory. nullopt when there is none.
std::optional<std::string> findProgram(const std::string& program);

// Runs argv[0] (searched on $PATH) with these arguments and waits for it. Its stdin is /dev/null; with
// `quiet` its stdout and stderr go to /dev/null too. Returns its exit status, 128 + the signal that
// ended it, or 127 when it could not be started (as a shell would).
int runProcess(const std::vector<std::string>& argv, bool quiet = false);

}  // namespace drape
