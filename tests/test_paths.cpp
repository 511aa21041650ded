#include "test_paths.hpp"

#include <algorithm>
#include <filesystem>

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

}  // namespace drape::test
