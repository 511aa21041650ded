// The exit statuses every command shares and the error that carries one (docs/exit-status.md). Apart from
// commands.hpp so that the code the commands call (exports, the solver factory, the video) need not parse
// CLI11's headers: 9 s of compile time each on the 2-core CI machine.
#pragma once

#include <stdexcept>
#include <string>

namespace drape {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // anything unexpected
inline constexpr int kExitBadInput = 2;  // scene file, option values
inline constexpr int kExitNoGl = 3;      // no OpenGL 4.5 context for --solver gpu / render / view
inline constexpr int kExitBlowUp = 4;    // the simulation became non-finite or ran away

// Thrown by commands to leave with a given status and one line on stderr.
class CommandError : public std::runtime_error {
 public:
  CommandError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

}  // namespace drape
