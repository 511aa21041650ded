// Compiling shader programs from files under glsl/, with variant #defines. Errors throw ShaderError
// with the file and line the compiler complained about (not the line in the assembled text).
// A viewer that reloads shaders keeps its old Program when this throws.
#pragma once

#include "gl/objects.hpp"
#include "gl/shader_source.hpp"

#include <filesystem>
#include <string>

namespace drape::gl {

// `file` is relative to glslRoot() (absolute paths are used as they are), e.g. "sim/forces_integrate.comp".
Program compileCompute(const std::filesystem::path& file, const Defines& defines = {});

// A compute program from text (no #version, no #include) rather than a file: for small programs
// built into the code, such as the timer-query probe. label names it in errors.
Program compileComputeText(const std::string& text, const std::string& label, const Defines& defines = {});

// Vertex + fragment (+ optional geometry) program; the same defines go to every stage.
Program compileGraphics(const std::filesystem::path& vert, const std::filesystem::path& frag,
                        const Defines& defines = {}, const std::filesystem::path& geom = {});

}  // namespace drape::gl
