// Where the tests find the source tree and the drape they run. Functions, not the compile definitions
// themselves, so that only test_paths.cpp names the checkout: every other test compiles to the same bytes in
// any clone and a fresh clone's build reuses the compiler cache (tools/test).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace drape::test {

const char* sourceDir();    // the source tree this build was configured from
const char* drapeBinary();  // the build's drape executable
// The bundled scenes' names (scenes/*.json without the extension), sorted.
std::vector<std::string> bundledSceneNames();

// A fresh directory under the system's temporary one, named `prefix` and the process id, removed with the
// object (a static one at exit): tests leave nothing behind in /tmp.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace drape::test
