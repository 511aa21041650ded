// Output files are written whole or not at all: to a temporary file beside the target, then renamed.
#pragma once

#include "core/metrics.hpp"

#include <string>

namespace drape {

void writeFileAtomically(const std::string& path, const std::string& contents);
void writePositionsJson(const std::string& path, const Positions& x);

}  // namespace drape
