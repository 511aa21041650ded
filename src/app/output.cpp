#include "app/output.hpp"

#include "app/commands.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace drape {

void writeFileAtomically(const std::string& path, const std::string& contents) {
  const std::string tmp = path + ".partial";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw CommandError(kExitBadInput, fmt::format("{}: cannot open for writing", path));
    out << contents;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw CommandError(kExitFailure, fmt::format("{}: write failed", path));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw CommandError(kExitFailure, fmt::format("{}: {}", path, ec.message()));
  }
}

void writePositionsJson(const std::string& path, const Positions& x) {
  std::string s = "[\n";
  for (std::size_t i = 0; i < x.size(); ++i)
    s += fmt::format("[{:.9g},{:.9g},{:.9g}]{}\n", x[i].x, x[i].y, x[i].z, i + 1 < x.size() ? "," : "");
  s += "]\n";
  writeFileAtomically(path, s);
}

}  // namespace drape
