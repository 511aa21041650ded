// OpenGL 4.5 core contexts: headless through EGL (tests, benchmarks, `drape render`) and a GLFW
// window (the interactive viewer). Creating either loads the glad function pointers.
#pragma once

#include "gl/debug.hpp"

#include <glm/vec2.hpp>

#include <stdexcept>
#include <string>

struct GLFWwindow;

namespace drape::gl {

// What the driver reports about the current context, read once when the context is made.
struct ContextInfo {
  std::string vendor;        // GL_VENDOR
  std::string renderer;      // GL_RENDERER: always log it, it tells llvmpipe from a GPU
  std::string version;       // GL_VERSION
  std::string glsl_version;  // GL_SHADING_LANGUAGE_VERSION
  bool software = false;     // llvmpipe / softpipe / swrast: a correctness target, never timed
  std::string platform;      // how it was made: "EGL device 1 (/dev/dri/card0)", "EGL surfaceless", "GLFW"
};

// No usable context. The message says what was tried and what was missing.
class ContextError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct HeadlessOptions {
  bool debug = false;           // debug context + enableDebugOutput(true)
  bool prefer_hardware = true;  // skip Mesa's software device while a hardware one gives 4.5 core
  // Only this EGL platform: "device" or "surfaceless"; empty tries both. $DRAPE_EGL_PLATFORM
  // overrides it, to diagnose a machine without recompiling.
  std::string platform;
};

// An EGL context with no surface, current on the creating thread. Render into Framebuffers.
// Tries EGL_EXT_platform_device devices (hardware first when prefer_hardware, because Mesa lists
// its software device first), then the Mesa surfaceless platform.
class HeadlessContext {
 public:
  HeadlessContext() = default;  // empty: no context, no EGL call
  static HeadlessContext create(const HeadlessOptions& options = {});

  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;
  HeadlessContext(HeadlessContext&& other) noexcept;
  HeadlessContext& operator=(HeadlessContext&& other) noexcept;
  ~HeadlessContext();

  const ContextInfo& info() const { return info_; }
  void makeCurrent() const;
  explicit operator bool() const { return context_ != nullptr; }

 private:
  void release() noexcept;

  void* display_ = nullptr;  // EGLDisplay; kept opaque so callers do not pull in EGL headers
  void* context_ = nullptr;  // EGLContext
  ContextInfo info_;
};

// A GLFW window with a 4.5 core, forward-compatible context, current on the creating thread.
class WindowContext {
 public:
  WindowContext() = default;  // empty: no window, no GLFW call
  // Throws ContextError when there is no display or the driver offers no 4.5 core context.
  // debug: a debug context whose GL errors are printed and recorded (enableDebugOutput(false)),
  // so the viewer keeps running.
  static WindowContext create(int width, int height, const std::string& title, bool visible = true, bool debug = false);

  WindowContext(const WindowContext&) = delete;
  WindowContext& operator=(const WindowContext&) = delete;
  WindowContext(WindowContext&& other) noexcept;
  WindowContext& operator=(WindowContext&& other) noexcept;
  ~WindowContext();

  GLFWwindow* window() const { return window_; }
  const ContextInfo& info() const { return info_; }
  glm::ivec2 framebufferSize() const;  // pixels, which differ from window units on HiDPI screens
  void makeCurrent() const;

 private:
  void release() noexcept;

  GLFWwindow* window_ = nullptr;
  ContextInfo info_;
};

// One line for logs: "renderer | GL version | vendor".
std::string describe(const ContextInfo& info);

// Reads ContextInfo from the current context.
ContextInfo queryContextInfo();

}  // namespace drape::gl
