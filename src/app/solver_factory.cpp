#include "app/solver_factory.hpp"

#include "app/commands.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl/context.hpp"
#include "gpu/gpu_solver.hpp"

#include <fmt/format.h>

namespace drape {

namespace {

std::unique_ptr<Solver> makeGpuSolver(const Scene& scene, bool verbose) {
  gl::HeadlessContext context;
  try {
    context = gl::HeadlessContext::create();
  } catch (const gl::ContextError& e) {
    throw CommandError(kExitNoGl, fmt::format("gpu solver: {}", e.what()));
  }
  if (verbose)
    fmt::print(stderr, "gpu solver: GL_RENDERER {} | GL_VERSION {} ({})\n", context.info().renderer,
               context.info().version, context.info().platform);
  try {
    // The solver owns the context, so the context lives exactly as long as the solver's GL objects.
    return std::make_unique<GpuSolver>(scene, GpuSolverOptions{}, std::move(context));
  } catch (const GpuLimitError& e) {
    throw CommandError(kExitBadInput, fmt::format("{}: {}", scene.path, e.what()));
  }
}

}  // namespace

std::unique_ptr<Solver> makeSolver(const Scene& scene, const std::string& name, bool verbose, int threads) {
  if (name == "cpu") return std::make_unique<CpuSolver<float>>(scene, CpuSolverOptions{.threads = threads});
  if (name == "cpu64") return std::make_unique<CpuSolver<double>>(scene, CpuSolverOptions{.threads = threads});
  if (name == "gpu") return makeGpuSolver(scene, verbose);
  throw CommandError(kExitBadInput, fmt::format("--solver: unknown solver '{}' (cpu, cpu64, gpu)", name));
}

std::string describePasses(const Solver& solver) {
  const std::vector<std::string> passes = solver.passes(), frame_passes = solver.framePasses();
  const int substeps = solver.scene().sim.steps_per_frame;
  std::string out;
  if (solver.dispatchesPerFrame() > 0) {
    out = fmt::format("{}: {} dispatches per substep, {} per frame ({} substeps", solver.name(), passes.size(),
                      solver.dispatchesPerFrame(), substeps);
    out += frame_passes.empty() ? ")\n" : fmt::format(", then {} once per frame)\n", frame_passes.size());
  } else {
    out = fmt::format("{}: {} passes per substep, {} substeps per frame\n", solver.name(), passes.size(), substeps);
  }
  // A pass dispatched several times in a row (the stretch limit's colours) is one line with its count.
  std::size_t line = 1;
  const auto list = [&out, &line](const std::vector<std::string>& names) {
    for (std::size_t i = 0; i < names.size(); ++line) {
      std::size_t run = 1;
      while (i + run < names.size() && names[i + run] == names[i])
        ++run;
      out += run == 1 ? fmt::format("  {}. {}\n", line, names[i]) : fmt::format("  {}. {} x{}\n", line, names[i], run);
      i += run;
    }
  };
  list(passes);
  if (!frame_passes.empty()) {
    out += "  then once per frame, after the last substep:\n";
    list(frame_passes);
  }
  return out;
}

}  // namespace drape
