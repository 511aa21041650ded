#include "gl/context.hpp"

#include "gl/display_libraries.hpp"
#include "gl/gl.hpp"

#define EGL_NO_X11  // keep Xlib's macros (None, Bool, Status) out of this file
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

namespace drape::gl {
namespace {

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[length] == '\0' || p[length] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error " + std::to_string(error);
  }
}

template <class Function>
Function eglFunction(const char* name) {
  return reinterpret_cast<Function>(eglGetProcAddress(name));
}

bool isSoftwareRenderer(const std::string& renderer) {
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "SWR", "Software Rasterizer"})
    if (renderer.find(name) != std::string::npos) return true;
  return false;
}

// One EGL display to try: a device of EGL_EXT_platform_device or the Mesa surfaceless platform.
struct Candidate {
  std::string label;
  EGLenum platform;
  void* native;
  bool software;  // known before creating a context (EGL_MESA_device_software)
};

bool hasRenderNode() {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/dev/dri", error))
    if (entry.path().filename().string().rfind("renderD", 0) == 0) return true;
  return false;
}

std::vector<Candidate> listCandidates(bool prefer_hardware, const std::string& platform,
                                      std::vector<std::string>& tried) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::vector<Candidate> devices;
  if (platform == "surfaceless") {
    tried.push_back("no device platform (platform \"surfaceless\" asked for)");
  } else if (hasExtension(client, "EGL_EXT_platform_device") && hasExtension(client, "EGL_EXT_device_enumeration")) {
    auto queryDevices = eglFunction<PFNEGLQUERYDEVICESEXTPROC>("eglQueryDevicesEXT");
    auto queryDeviceString = eglFunction<PFNEGLQUERYDEVICESTRINGEXTPROC>("eglQueryDeviceStringEXT");
    EGLint count = 0;
    if (queryDevices && queryDevices(0, nullptr, &count) && count > 0) {
      std::vector<EGLDeviceEXT> handles(static_cast<std::size_t>(count));
      queryDevices(count, handles.data(), &count);
      for (EGLint i = 0; i < count; ++i) {
        const char* extensions = queryDeviceString ? queryDeviceString(handles[i], EGL_EXTENSIONS) : nullptr;
        const bool software = hasExtension(extensions, "EGL_MESA_device_software");
        std::string label = "EGL device " + std::to_string(i);
        if (software) {
          label += " (software)";
        } else if (hasExtension(extensions, "EGL_EXT_device_drm")) {
          if (const char* file = queryDeviceString(handles[i], EGL_DRM_DEVICE_FILE_EXT))
            label += std::string(" (") + file + ")";
        }
        devices.push_back({label, EGL_PLATFORM_DEVICE_EXT, handles[i], software});
      }
    }
    tried.push_back("device platform (" + std::to_string(devices.size()) +
                    (devices.size() == 1 ? " device)" : " devices)"));
  } else {
    tried.push_back("device platform (not supported by this EGL)");
  }
  if (prefer_hardware) {
    std::stable_partition(devices.begin(), devices.end(), [](const Candidate& c) { return !c.software; });
  }
  if (platform == "device") {
    tried.push_back("no surfaceless platform (platform \"device\" asked for)");
  } else if (hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    // Mesa's surfaceless platform renders on a DRM render node when there is one, else in software.
    devices.push_back({"EGL surfaceless", EGL_PLATFORM_SURFACELESS_MESA, nullptr, !hasRenderNode()});
    tried.push_back("surfaceless platform");
  } else {
    tried.push_back("surfaceless platform (not supported by this EGL)");
  }
  return devices;
}

// The GL version a display offers without asking for 4.5 core, for the error message.
std::string probeDefaultVersion(EGLDisplay display, EGLConfig config) {
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
  if (context == EGL_NO_CONTEXT) return "no context at all";
  std::string version = "unknown";
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    using GetString = const GLubyte* (*)(GLenum);
    if (auto getString = eglFunction<GetString>("glGetString")) {
      if (const GLubyte* text = getString(GL_VERSION)) version = reinterpret_cast<const char*>(text);
    }
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  eglDestroyContext(display, context);
  return version;
}

struct Created {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ContextInfo info;
};

// Creates and makes current a 4.5 core context on one candidate; on failure returns why.
// Displays are not terminated on failure: EGL displays are per-platform singletons whose
// initialisation is not reference counted, so terminating one could break another context.
std::variant<Created, std::string> tryCandidate(const Candidate& candidate, bool debug) {
  auto getPlatformDisplay = eglFunction<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
  if (!getPlatformDisplay) return std::string("no eglGetPlatformDisplayEXT");
  EGLDisplay display = getPlatformDisplay(candidate.platform, candidate.native, nullptr);
  if (display == EGL_NO_DISPLAY) return "no display (" + eglErrorName(eglGetError()) + ")";
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return "eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
  if (!eglBindAPI(EGL_OPENGL_API)) return std::string("no desktop OpenGL API");
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context")) return std::string("no EGL_KHR_surfaceless_context");

  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
    // Surface type 0 matches every config: the context never gets a surface.
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &count) || count == 0) return std::string("no OpenGL config");
  }
  const bool egl15 = major > 1 || (major == 1 && minor >= 5);
  std::vector<EGLint> attributes = {EGL_CONTEXT_MAJOR_VERSION_KHR,       4,
                                    EGL_CONTEXT_MINOR_VERSION_KHR,       5,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR};
  if (debug) {
    if (egl15) {
      attributes.insert(attributes.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
    } else {
      attributes.insert(attributes.end(), {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
    }
  }
  attributes.push_back(EGL_NONE);
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes.data());
  if (context == EGL_NO_CONTEXT) {
    const std::string error = eglErrorName(eglGetError());
    return "no OpenGL 4.5 core context (" + error + "; got " + probeDefaultVersion(display, config) + ")";
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    const std::string error = eglErrorName(eglGetError());
    eglDestroyContext(display, context);
    return "eglMakeCurrent without a surface failed (" + error + ")";
  }
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(eglGetProcAddress));
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 45) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return "glad loaded GL " + std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
           std::to_string(GLAD_VERSION_MINOR(version)) + ", not 4.5";
  }
  Created created{display, context, queryContextInfo()};
  created.info.platform = candidate.label;
  return created;
}

std::string glfwLastError;

void onGlfwError(int /*code*/, const char* description) {
  glfwLastError = description ? description : "unknown";
}

int liveWindows = 0;

}  // namespace

ContextInfo queryContextInfo() {
  const auto text = [](GLenum name) {
    const GLubyte* value = glGetString(name);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string();
  };
  ContextInfo info;
  info.vendor = text(GL_VENDOR);
  info.renderer = text(GL_RENDERER);
  info.version = text(GL_VERSION);
  info.glsl_version = text(GL_SHADING_LANGUAGE_VERSION);
  info.software = isSoftwareRenderer(info.renderer);
  return info;
}

std::string describe(const ContextInfo& info) {
  return info.renderer + " | " + info.version + " | " + info.vendor;
}

HeadlessContext HeadlessContext::create(const HeadlessOptions& options) {
  if (const std::string error = openDisplayLibrary(DisplayLibrary::Egl); !error.empty())
    throw ContextError("EGL: " + error);
  std::vector<std::string> tried;
  std::string platform = options.platform;
  if (const char* forced = std::getenv("DRAPE_EGL_PLATFORM"); forced && *forced) platform = forced;
  if (!platform.empty() && platform != "device" && platform != "surfaceless")
    throw ContextError("EGL: unknown platform '" + platform +
                       "' (DRAPE_EGL_PLATFORM or HeadlessOptions::platform): "
                       "expected device or surfaceless");
  const std::vector<Candidate> candidates = listCandidates(options.prefer_hardware, platform, tried);
  std::vector<std::string> failures;
  std::optional<Created> software_fallback;
  const auto destroy = [](const Created& c) {
    eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(c.display, c.context);
  };
  std::optional<Created> chosen;
  for (const Candidate& candidate : candidates) {
    // One software context is as good as another: skip the cost of making a second.
    if (candidate.software && software_fallback) continue;
    auto result = tryCandidate(candidate, options.debug);
    if (auto* failure = std::get_if<std::string>(&result)) {
      failures.push_back(candidate.label + ": " + *failure);
      continue;
    }
    Created created = std::get<Created>(std::move(result));
    // A device may turn out to be software only once its context reports GL_RENDERER.
    if (options.prefer_hardware && created.info.software) {
      if (software_fallback) {
        destroy(created);
      } else {
        software_fallback = std::move(created);
      }
      continue;
    }
    chosen = std::move(created);
    break;
  }
  if (chosen && software_fallback) destroy(*software_fallback);
  if (!chosen) chosen = std::move(software_fallback);
  if (!chosen) {
    std::string message = "EGL: tried ";
    for (std::size_t i = 0; i < tried.size(); ++i)
      message += (i ? " and " : "") + tried[i];
    message += ": no OpenGL 4.5 core context";
    for (const std::string& failure : failures)
      message += "; " + failure;
    throw ContextError(message);
  }

  HeadlessContext context;
  context.display_ = chosen->display;
  context.context_ = chosen->context;
  context.info_ = chosen->info;
  // The software fallback may have been made current before a later candidate was tried.
  context.makeCurrent();
  gladLoadGL(reinterpret_cast<GLADloadfunc>(eglGetProcAddress));
  if (options.debug) enableDebugOutput(true);
  return context;
}

HeadlessContext::HeadlessContext(HeadlessContext&& other) noexcept
    : display_(std::exchange(other.display_, nullptr)),
      context_(std::exchange(other.context_, nullptr)),
      info_(std::move(other.info_)) {}

HeadlessContext& HeadlessContext::operator=(HeadlessContext&& other) noexcept {
  if (this != &other) {
    release();
    display_ = std::exchange(other.display_, nullptr);
    context_ = std::exchange(other.context_, nullptr);
    info_ = std::move(other.info_);
  }
  return *this;
}

HeadlessContext::~HeadlessContext() {
  release();
}

void HeadlessContext::release() noexcept {
  if (context_ == nullptr) return;
  if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  context_ = nullptr;
  display_ = nullptr;
}

void HeadlessContext::makeCurrent() const {
  if (context_ == nullptr) throw ContextError("EGL: makeCurrent on an empty HeadlessContext");
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw ContextError("EGL: eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
}

WindowContext WindowContext::create(int width, int height, const std::string& title, bool visible, bool debug) {
  if (const std::string error = openDisplayLibrary(DisplayLibrary::Glfw); !error.empty())
    throw ContextError("GLFW: " + error);
  glfwSetErrorCallback(onGlfwError);
  if (liveWindows == 0 && !glfwInit()) {
    throw ContextError("GLFW: cannot initialise (" + glfwLastError +
                       "); a window needs a display, e.g. run under xvfb-run, or use the headless commands");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    const std::string error = glfwLastError;
    if (liveWindows == 0) glfwTerminate();
    throw ContextError("GLFW: no OpenGL 4.5 core context for a " + std::to_string(width) + "x" +
                       std::to_string(height) + " window (" + error + ")");
  }
  ++liveWindows;
  WindowContext context;
  context.window_ = window;
  glfwMakeContextCurrent(window);
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress));
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 45) {
    throw ContextError("GLFW: glad loaded GL " + std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                       std::to_string(GLAD_VERSION_MINOR(version)) + ", not 4.5");
  }
  context.info_ = queryContextInfo();
  context.info_.platform = "GLFW";
  // The viewer reports errors and keeps running; only headless runs turn them into exceptions.
  if (debug) enableDebugOutput(false);
  return context;
}

WindowContext::WindowContext(WindowContext&& other) noexcept
    : window_(std::exchange(other.window_, nullptr)), info_(std::move(other.info_)) {}

WindowContext& WindowContext::operator=(WindowContext&& other) noexcept {
  if (this != &other) {
    release();
    window_ = std::exchange(other.window_, nullptr);
    info_ = std::move(other.info_);
  }
  return *this;
}

WindowContext::~WindowContext() {
  release();
}

void WindowContext::release() noexcept {
  if (window_ == nullptr) return;
  glfwDestroyWindow(window_);
  window_ = nullptr;
  if (--liveWindows == 0) glfwTerminate();
}

glm::ivec2 WindowContext::framebufferSize() const {
  glm::ivec2 size{0};
  if (window_) glfwGetFramebufferSize(window_, &size.x, &size.y);
  return size;
}

void WindowContext::makeCurrent() const {
  if (window_ == nullptr) throw ContextError("GLFW: makeCurrent on an empty WindowContext");
  glfwMakeContextCurrent(window_);
}

}  // namespace drape::gl
