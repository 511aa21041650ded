// Makes the solver a command asked for by name: "cpu" (float), "cpu64" (double), "gpu".
#pragma once

#include "core/solver.hpp"

#include <memory>
#include <string>

namespace drape {

// "gpu" makes its own headless GL 4.5 context, owned by the solver (it makes that context current);
// without one it throws CommandError(kExitNoGl, "gpu solver: <what was tried>: <what is missing>").
// A scene too large for the GPU throws CommandError(kExitBadInput, ...) before anything is dispatched.
// verbose: logs GL_RENDERER and GL_VERSION of the context to stderr. threads: the CPU solvers' OpenMP
// threads (0 = every core; the bytes they compute do not depend on it).
std::unique_ptr<Solver> makeSolver(const Scene& scene, const std::string& name, bool verbose = false, int threads = 0);

// Readable listing of the passes per substep and dispatches per frame (for --verbose), e.g.
//   gpu: 2 dispatches per substep, 60 per frame (30 substeps)
//     1. forces+integrate
//     2. limit_stretch
std::string describePasses(const Solver& solver);

}  // namespace drape
