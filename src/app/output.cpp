#include "app/output.hpp"

#include "core/memory_stage.hpp"

#include <fmt/format.h>

namespace drape {

void writePositionsJson(const std::string& path, const Positions& x) {
  const MemoryStage stage("writing " + path);
  std::string s = "[\n";
  for (std::size_t i = 0; i < x.size(); ++i)
    s += fmt::format("[{:.9g},{:.9g},{:.9g}]{}\n", x[i].x, x[i].y, x[i].z, i + 1 < x.size() ? "," : "");
  s += "]\n";
  writeFileAtomically(path, s);
}

}  // namespace drape
