// Shell quoting for the command-line tests, which run `drape` through /bin/sh, and the file name that
// would run a command if drape ever pasted it into a shell command line itself.
#pragma once

#include <string>

namespace drape::testing {

// Single-quoted for /bin/sh, whatever the text holds.
inline std::string quote(const std::string& text) {
  std::string out = "'";
  for (char c : text)
    out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// A name that runs `touch PWNED` wherever it is pasted into a shell command inside single quotes.
inline const std::string kHostile = "x';touch PWNED;'";

}  // namespace drape::testing
