// The display libraries, GLFW and EGL, opened when a command first makes a GL context rather than when drape starts.
// Linked in, they and the X11 chain they bring (eleven libraries of the twenty) were mapped, relocated and torn
// down by every run, `drape simulate` on the CPU too: 0.59 ms of a 4.4 ms run of no frames on the development
// machine (docs/results/cpu_speed.md). Their functions are defined in display_libraries.cpp, each calling the one
// of the opened library, so that the code calling them, ImGui's GLFW backend too, is written as if linked.
#pragma once

#include <string>

namespace drape::gl {

enum class DisplayLibrary { Glfw, Egl };

// Opens `library` (once; later calls return at once): an empty string, or why it cannot be opened, with the
// library's file and the Debian package that has it. Every function of the library may be called after success.
std::string openDisplayLibrary(DisplayLibrary library);

namespace detail {
// dlopen of `file` into `handle`: an empty string, or why not, naming `file` and `package`
std::string openLibrary(const char* file, const char* package, void*& handle);
}  // namespace detail

}  // namespace drape::gl
