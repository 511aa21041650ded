#include "gl/display_libraries.hpp"

#define EGL_NO_X11  // keep Xlib's macros (None, Bool, Status) out of this file
#include <EGL/egl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace drape::gl {
namespace {

struct Library {
  Library(const char* soname, const char* debian_package) : file(soname), package(debian_package) {}
  const char* file;     // the soname the linker would have recorded
  const char* package;  // Debian's, for the message
  std::once_flag once;
  void* handle = nullptr;
  std::string error;
};

Library& library(DisplayLibrary which) {
  static Library glfw{"libglfw.so.3", "libglfw3"}, egl{"libEGL.so.1", "libegl1"};
  return which == DisplayLibrary::Glfw ? glfw : egl;
}

// The library's function `name`, for its definition below. The commands open the library before they call any
// (openDisplayLibrary, where a context is made, with a message of their own): reaching a failure here means a call
// before that, which is reported and ends the run rather than jumping to null.
void* function(DisplayLibrary which, const char* name) {
  Library& lib = library(which);
  std::string error = openDisplayLibrary(which);
  void* f = error.empty() ? dlsym(lib.handle, name) : nullptr;
  if (f == nullptr) {
    if (error.empty()) error = std::string(lib.file) + " has no " + name;
    std::fprintf(stderr, "drape: %s\n", error.c_str());
    std::exit(EXIT_FAILURE);
  }
  return f;
}

}  // namespace

std::string openDisplayLibrary(DisplayLibrary which) {
  Library& lib = library(which);
  std::call_once(lib.once, [&lib] { lib.error = detail::openLibrary(lib.file, lib.package, lib.handle); });
  return lib.error;
}

std::string detail::openLibrary(const char* file, const char* package, void*& handle) {
  // Local: its symbols serve only the definitions below, which look each one up in it
  handle = dlopen(file, RTLD_NOW | RTLD_LOCAL);
  if (handle != nullptr) return {};
  const char* why = dlerror();
  return std::string("cannot open ") + file + " (" + (why ? why : "no reason given") + "; Debian's package " + package +
         " has it)";
}

}  // namespace drape::gl

// Each function the program calls, defined with the header's declaration and calling the library's own, looked up
// once (a function-local static).
#define DRAPE_DISPLAY_FUNCTION(library, result, name, parameters, arguments)                               \
  extern "C" result name parameters {                                                                      \
    static const auto real =                                                                               \
        reinterpret_cast<decltype(&name)>(drape::gl::function(drape::gl::DisplayLibrary::library, #name)); \
    return real arguments;                                                                                 \
  }

DRAPE_DISPLAY_FUNCTION(Egl, EGLBoolean, eglBindAPI, (EGLenum api), (api))
DRAPE_DISPLAY_FUNCTION(Egl, EGLBoolean, eglChooseConfig,
                       (EGLDisplay display, const EGLint* attributes, EGLConfig* configs, EGLint size, EGLint* count),
                       (display, attributes, configs, size, count))
DRAPE_DISPLAY_FUNCTION(Egl, EGLContext, eglCreateContext,
                       (EGLDisplay display, EGLConfig config, EGLContext share, const EGLint* attributes),
                       (display, config, share, attributes))
DRAPE_DISPLAY_FUNCTION(Egl, EGLBoolean, eglDestroyContext, (EGLDisplay display, EGLContext context), (display, context))
DRAPE_DISPLAY_FUNCTION(Egl, EGLContext, eglGetCurrentContext, (void), ())
DRAPE_DISPLAY_FUNCTION(Egl, EGLint, eglGetError, (void), ())
DRAPE_DISPLAY_FUNCTION(Egl, __eglMustCastToProperFunctionPointerType, eglGetProcAddress, (const char* name), (name))
DRAPE_DISPLAY_FUNCTION(Egl, EGLBoolean, eglInitialize, (EGLDisplay display, EGLint* major, EGLint* minor),
                       (display, major, minor))
DRAPE_DISPLAY_FUNCTION(Egl, EGLBoolean, eglMakeCurrent,
                       (EGLDisplay display, EGLSurface draw, EGLSurface read, EGLContext context),
                       (display, draw, read, context))
DRAPE_DISPLAY_FUNCTION(Egl, const char*, eglQueryString, (EGLDisplay display, EGLint name), (display, name))

// The viewer's and ImGui's GLFW backend's
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWcursor*, glfwCreateStandardCursor, (int shape), (shape))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWwindow*, glfwCreateWindow,
                       (int width, int height, const char* title, GLFWmonitor* monitor, GLFWwindow* share),
                       (width, height, title, monitor, share))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwDestroyCursor, (GLFWcursor * cursor), (cursor))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwDestroyWindow, (GLFWwindow * window), (window))
DRAPE_DISPLAY_FUNCTION(Glfw, const char*, glfwGetClipboardString, (GLFWwindow * window), (window))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwGetCursorPos, (GLFWwindow * window, double* x, double* y), (window, x, y))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwGetFramebufferSize, (GLFWwindow * window, int* width, int* height),
                       (window, width, height))
DRAPE_DISPLAY_FUNCTION(Glfw, int, glfwGetInputMode, (GLFWwindow * window, int mode), (window, mode))
DRAPE_DISPLAY_FUNCTION(Glfw, const float*, glfwGetJoystickAxes, (int joystick, int* count), (joystick, count))
DRAPE_DISPLAY_FUNCTION(Glfw, const unsigned char*, glfwGetJoystickButtons, (int joystick, int* count),
                       (joystick, count))
DRAPE_DISPLAY_FUNCTION(Glfw, int, glfwGetMouseButton, (GLFWwindow * window, int button), (window, button))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWglproc, glfwGetProcAddress, (const char* name), (name))
DRAPE_DISPLAY_FUNCTION(Glfw, double, glfwGetTime, (void), ())
DRAPE_DISPLAY_FUNCTION(Glfw, int, glfwGetWindowAttrib, (GLFWwindow * window, int attribute), (window, attribute))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwGetWindowSize, (GLFWwindow * window, int* width, int* height),
                       (window, width, height))
DRAPE_DISPLAY_FUNCTION(Glfw, void*, glfwGetWindowUserPointer, (GLFWwindow * window), (window))
DRAPE_DISPLAY_FUNCTION(Glfw, int, glfwInit, (void), ())
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwMakeContextCurrent, (GLFWwindow * window), (window))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwPollEvents, (void), ())
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWcharfun, glfwSetCharCallback, (GLFWwindow * window, GLFWcharfun callback),
                       (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSetClipboardString, (GLFWwindow * window, const char* text), (window, text))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSetCursor, (GLFWwindow * window, GLFWcursor* cursor), (window, cursor))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWcursorenterfun, glfwSetCursorEnterCallback,
                       (GLFWwindow * window, GLFWcursorenterfun callback), (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSetCursorPos, (GLFWwindow * window, double x, double y), (window, x, y))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWcursorposfun, glfwSetCursorPosCallback,
                       (GLFWwindow * window, GLFWcursorposfun callback), (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWerrorfun, glfwSetErrorCallback, (GLFWerrorfun callback), (callback))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSetInputMode, (GLFWwindow * window, int mode, int value), (window, mode, value))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWkeyfun, glfwSetKeyCallback, (GLFWwindow * window, GLFWkeyfun callback),
                       (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWmonitorfun, glfwSetMonitorCallback, (GLFWmonitorfun callback), (callback))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWmousebuttonfun, glfwSetMouseButtonCallback,
                       (GLFWwindow * window, GLFWmousebuttonfun callback), (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWscrollfun, glfwSetScrollCallback, (GLFWwindow * window, GLFWscrollfun callback),
                       (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, GLFWwindowfocusfun, glfwSetWindowFocusCallback,
                       (GLFWwindow * window, GLFWwindowfocusfun callback), (window, callback))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSetWindowUserPointer, (GLFWwindow * window, void* pointer), (window, pointer))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwSwapBuffers, (GLFWwindow * window), (window))
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwTerminate, (void), ())
DRAPE_DISPLAY_FUNCTION(Glfw, void, glfwWindowHint, (int hint, int value), (hint, value))
DRAPE_DISPLAY_FUNCTION(Glfw, int, glfwWindowShouldClose, (GLFWwindow * window), (window))
