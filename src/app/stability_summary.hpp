// What `drape stability` shows on the terminal: a count and an estimate of the time left on each finished
// run's line, and at the end a short table per integrator and substep count (the full one is in
// stability.md).
#pragma once

#include "app/stability_cases.hpp"

#include <string>
#include <vector>

namespace drape {

// A run's cost for the time-left estimate, in point-substeps: frames x substeps x points, VBD's substep
// counted twice (it costs about twice Verlet's on the CPU: docs/results/README.md, "Speed with VBD"). A
// guarded run counts the substeps the guard will choose.
double stabilityRunCost(const StabilityCase& c, int steps, bool guard);

// One row per integrator and substep count (Verlet's guarded runs a row of their own): the runs that keep
// their shape (stable, no spring past kShapeStrain) and the stable ones, of all; the largest ks of the sweep
// that keeps its shape and that runs stable; and the first unstable runs with their frames.
std::string stabilitySummary(const StabilityReport& report, const std::vector<StabilityCase>& cases);

}  // namespace drape
