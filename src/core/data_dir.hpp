// Where drape finds the files it reads at run time: shaders (glsl/), textures (textures/), the bundled
// scenes (scenes/) and the plot script (tools/). One lookup, so that an installed drape and the one in a
// build tree find them by the same rule.
#pragma once

#include <filesystem>
#include <string>

namespace drape {

// The directory `name` ("glsl", "textures", "scenes", "tools"), looked for in this order:
//  1. $`env`, when `env` is given and that variable is set and not empty;
//  2. <prefix>/share/drape/<name> when the running executable is <prefix>/bin/drape and that
//     directory exists (`cmake --install` puts them there);
//  3. the source tree this drape was built from (DRAPE_SOURCE_DIR), for the build tree's binary only (one
//     in the build directory it was built in); any other drape gets 2.'s path, present or not.
std::filesystem::path dataDir(const std::string& name, const char* env = nullptr);

// Whether `exe` is in the build directory this drape was built in (DRAPE_BUILD_DIR).
bool runsFromItsBuildTree(const std::filesystem::path& exe);

// The running executable (/proc/self/exe); empty when it cannot be read.
std::filesystem::path executablePath();

}  // namespace drape
