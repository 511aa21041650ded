// GL debug output (KHR_debug, core in 4.3): errors are recorded where they happen and surface as
// exceptions at the next call into this layer, never thrown from inside the driver's callback.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace drape::gl {

// A GL error reported through debug output (or a GL object in an unusable state).
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Installs glDebugMessageCallback on the current context, synchronous so that a message arrives
// inside the call that caused it. Errors (GL_DEBUG_TYPE_ERROR) and high-severity messages are
// recorded; medium-severity ones are printed to stderr; notifications are dropped.
// throw_on_error: the wrappers in objects.hpp and shader.hpp call checkDebugErrors() after their
// GL calls, so an error from them (or from raw GL calls made since the last check) throws
// GlError. Throwing from the callback itself would unwind through the driver's C frames.
// Without it, errors are only recorded (and printed) for takeDebugErrors().
void enableDebugOutput(bool throw_on_error);

// True when enableDebugOutput(true) is in effect.
bool debugErrorsThrow();

// Returns and clears the recorded errors, oldest first.
std::vector<std::string> takeDebugErrors();

// Throws GlError with every recorded error (and clears them) when there are any and errors throw;
// does nothing otherwise. Cheap: one atomic load when nothing was recorded.
void checkDebugErrors();

}  // namespace drape::gl
