#include "gl/debug.hpp"

#include "gl/gl.hpp"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <utility>

namespace drape::gl {
namespace {

std::mutex errors_mutex;
std::vector<std::string> recorded_errors;
std::atomic<bool> errors_pending{false};
std::atomic<bool> errors_throw{false};

const char* sourceName(GLenum source) {
  switch (source) {
    case GL_DEBUG_SOURCE_API:
      return "API";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
      return "window system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER:
      return "shader compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY:
      return "third party";
    case GL_DEBUG_SOURCE_APPLICATION:
      return "application";
    default:
      return "other";
  }
}

const char* typeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR:
      return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
      return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
      return "undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY:
      return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE:
      return "performance";
    default:
      return "message";
  }
}

void GLAD_API_PTR onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                 const GLchar* message, const void* /*user*/) {
  const std::string text =
      std::string("GL ") + typeName(type) + " (" + sourceName(source) + ", id " + std::to_string(id) +
      "): " + (length >= 0 ? std::string(message, static_cast<std::size_t>(length)) : std::string(message));
  // A failed compile is reported by ShaderError with its file and line; Mesa also sends it here.
  if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
  if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH) {
    if (!errors_throw) std::fprintf(stderr, "%s\n", text.c_str());
    const std::lock_guard lock(errors_mutex);
    recorded_errors.push_back(text);
    errors_pending = true;
  } else if (severity == GL_DEBUG_SEVERITY_MEDIUM) {
    std::fprintf(stderr, "%s\n", text.c_str());
  }
}

}  // namespace

void enableDebugOutput(bool throw_on_error) {
  errors_throw = throw_on_error;
  glEnable(GL_DEBUG_OUTPUT);
  // Synchronous: the message arrives inside the GL call that caused it, so the next check points at it.
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(onDebugMessage, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
}

bool debugErrorsThrow() {
  return errors_throw;
}

std::vector<std::string> takeDebugErrors() {
  const std::lock_guard lock(errors_mutex);
  errors_pending = false;
  return std::exchange(recorded_errors, {});
}

void checkDebugErrors() {
  if (!errors_pending || !errors_throw) return;
  std::string message;
  for (const std::string& error : takeDebugErrors())
    message += (message.empty() ? "" : "\n") + error;
  throw GlError(message);
}

}  // namespace drape::gl
