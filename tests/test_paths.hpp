// Where the tests find the source tree and the drape they run. Functions, not the compile definitions
// themselves, so that only test_paths.cpp names the checkout: every other test compiles to the same bytes in
// any clone and a fresh clone's build reuses the compiler cache (tools/test).
#pragma once

#include <string>
#include <vector>

namespace drape::test {

const char* sourceDir();    // the source tree this build was configured from
const char* drapeBinary();  // the build's drape executable
// The bundled scenes' names (scenes/*.json without the extension), sorted.
std::vector<std::string> bundledSceneNames();

}  // namespace drape::test
