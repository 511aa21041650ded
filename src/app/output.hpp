// Output files: written whole or not at all, never through a link or over a device (core/atomic_file).
#pragma once

#include "core/atomic_file.hpp"
#include "core/metrics.hpp"

#include <string>

namespace drape {

void writePositionsJson(const std::string& path, const Positions& x);

}  // namespace drape
