// The cheap blow-up check every long run applies after each frame, for any solver: the viewer pauses on
// it, `drape simulate` exits 4 on it, the measurement commands mark a run unstable with it.
#pragma once

#include "core/solver.hpp"

#include <string>

namespace drape {

// On the GPU the integrate kernel's health flags (a few bytes read back), on the CPU a scan of the
// positions for a non-finite coordinate or one beyond sane_bound (the GPU kernel's test). Empty while
// sane, else one line saying what happened.
std::string checkHealth(Solver& solver, double sane_bound = 1e5);

}  // namespace drape
