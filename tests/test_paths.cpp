#include "test_paths.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace drape::test {

const char* sourceDir() {
  return DRAPE_SOURCE_DIR;
}
const char* drapeBinary() {
  return DRAPE_BINARY;
}

std::vector<std::string> bundledSceneNames() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(sourceDir()) / "scenes"))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

TempDir::TempDir(const std::string& prefix)
    : path_(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ignored;  // a destructor must not throw; what cannot be removed stays
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace drape::test
