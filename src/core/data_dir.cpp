#include "core/data_dir.hpp"

#include <cstdlib>
#include <system_error>

namespace drape {

std::filesystem::path executablePath() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::filesystem::path() : exe;
}

bool runsFromItsBuildTree(const std::filesystem::path& exe) {
  std::error_code error;
  return std::filesystem::equivalent(exe.parent_path(), DRAPE_BUILD_DIR, error) && !error;
}

std::filesystem::path dataDir(const std::string& name, const char* env) {
  if (env)
    if (const char* dir = std::getenv(env); dir && *dir) return dir;
  // DRAPE_DATA_FROM_BIN is the install layout's data directory relative to its bin directory
  // ("../share/drape" for GNU's layout), so a copied or relocated prefix still finds its own files.
  if (const std::filesystem::path exe = executablePath(); !exe.empty()) {
    const std::filesystem::path installed = (exe.parent_path() / DRAPE_DATA_FROM_BIN / name).lexically_normal();
    std::error_code error;
    if (std::filesystem::is_directory(installed, error)) return installed;
    // A drape outside its build tree whose data is missing (a partial install, a copied binary) reads
    // nothing of the machine it was built on: the installed path, whose files it then fails to find by
    // that name, and --version says it is missing.
    if (!runsFromItsBuildTree(exe)) return installed;
  }
  return std::filesystem::path(DRAPE_SOURCE_DIR) / name;
}

}  // namespace drape
