#include "app/output.hpp"

#include "core/memory_stage.hpp"

#include <charconv>
#include <system_error>

namespace drape {

namespace {

// %.9g, as fmt's {:.9g} wrote it (both round correctly), without a format string per number: a 2048^2
// cloth is 12.6 million of them.
void appendNumber(std::string& s, double v) {
  char digits[32];
  const std::to_chars_result r = std::to_chars(digits, digits + sizeof digits, v, std::chars_format::general, 9);
  s.append(digits, r.ptr);
}

}  // namespace

void writePositionsJson(const std::string& path, const Positions& x) {
  const MemoryStage stage("writing " + path);
  std::string s = "[\n";
  s.reserve(x.size() * 36 + 4);
  for (std::size_t i = 0; i < x.size(); ++i) {
    s += '[';
    appendNumber(s, x[i].x);
    s += ',';
    appendNumber(s, x[i].y);
    s += ',';
    appendNumber(s, x[i].z);
    s += i + 1 < x.size() ? "],\n" : "]\n";
  }
  s += "]\n";
  writeFileAtomically(path, s);
}

}  // namespace drape
