// The one table of solvers by name, and the factory every command makes its solvers with: `simulate`,
// `render` and `view` one solver, the measurement commands (bench, accuracy) many.
#pragma once

#include "core/scene.hpp"
#include "core/solver.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

namespace gl {
class HeadlessContext;
}

struct SolverKind {
  const char* name;
  const char* description;  // for --help
  bool measurement_only;    // offered by bench and accuracy only
};

// "cpu"        CpuSolver<float>, displacement form (the GPU's arithmetic)
// "cpu64"      CpuSolver<double>
// "gpu"        GpuSolver (OpenGL 4.5 compute), the path chosen per device (GpuPath::Auto)
// "gpu-general", "gpu-tiled", "gpu-onedispatch"  GpuSolver forced onto one path (GpuPath)
// "cpu-xprev"  CpuSolver<float>, x_prev form (CS184's; measured for its round-off): measurement only
const std::vector<SolverKind>& solverKinds();
// The names for CLI::IsMember: every solver, or those that `simulate`, `render` and `view` run.
std::vector<std::string> solverNames(bool with_measurement_only);
// "gpu" or one of its forced paths.
bool isGpuSolver(const std::string& name);

// A solver that cannot run here (no GL 4.5 context, a grid beyond the GPU's limits), for a factory made
// with skip_unavailable: the measurement commands record the run as skipped with this reason.
class SkippedRun : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlInfo {
  std::string vendor, renderer, version, glsl_version, platform;
  bool software = false;       // llvmpipe and friends: timings are the CPU's, never the GPU's
  bool timer_queries = false;  // GL_TIME_ELAPSED works; otherwise passes are timed by glFinish + wall clock
};

struct SolverFactoryOptions {
  // Where GPU solvers run: the context that is current when make() is called (a window, the renderer's
  // headless one), or, by default, one headless context the factory makes at the first GPU request and
  // keeps current for every GPU solver it makes.
  bool use_current_context = false;
  // A GPU solver that cannot run here: SkippedRun (the measurement commands), or by default
  // CommandError, status 3 without a context and 2 for a cloth beyond the GPU's limits.
  bool skip_unavailable = false;
  bool verbose = false;  // log GL_RENDERER and GL_VERSION to stderr when the factory makes its context
};

struct SolverRequest {
  // Time every pass: the GPU's by timer queries, or glFinish around each where none work; the CPU's by the wall clock
  // (CpuSolverOptions::pass_timing). Off, timings() only counts them.
  bool pass_timing = false;
  int threads = 0;  // CPU solvers' OpenMP threads (0 = every core; the bytes do not depend on it)
  // CPU solvers: self-collision also between the pairs the springs hold (closer than 2 x thickness at rest),
  // as CS184 does, to measure what skipping them changes (CpuSolverOptions::skip_held_pairs false).
  bool collide_held_pairs = false;
  // CPU solvers: every substep on a team of `threads`, whatever the cloth's size and the team trial would say
  // (CpuSolverOptions::team_min_points 0), to measure the team against one thread.
  bool team_always = false;
  // CPU solvers: time each wait of a team's threads for each other (CpuSolverOptions::record_waits; describeWaits)
  bool record_waits = false;
};

// Makes solvers by name. It must outlive the solvers it made: it owns their GL context.
class SolverFactory {
 public:
  explicit SolverFactory(SolverFactoryOptions options = {});
  ~SolverFactory();
  SolverFactory(const SolverFactory&) = delete;
  SolverFactory& operator=(const SolverFactory&) = delete;

  // An unknown name is CommandError(kExitBadInput).
  std::unique_ptr<Solver> make(const Scene& scene, const std::string& name, SolverRequest request = {});
  // Set once a GPU solver was made.
  const GlInfo* glInfo() const { return gl_info_.renderer.empty() ? nullptr : &gl_info_; }

 private:
  std::unique_ptr<Solver> makeGpu(const Scene& scene, const std::string& name, const SolverRequest& request);
  [[noreturn]] void unavailable(int status, const std::string& why);  // throws SkippedRun or CommandError

  SolverFactoryOptions options_;
  std::unique_ptr<gl::HeadlessContext> context_;
  std::string no_context_;  // why no context could be made, once tried
  GlInfo gl_info_;
};

// Readable listing of the passes per substep and dispatches per frame (for --verbose), e.g.
//   gpu: 2 dispatches per substep, 61 per frame (30 substeps, then 1 once per frame)
//     1. forces+integrate
//     2. limit_stretch
//     then once per frame, after the last substep:
//     3. health
std::string describePasses(const Solver& solver);
// The CPU solvers' self-collision candidates after a run: list entries a point, builds, the stencil's offsets
// (cpu/collision_pairs.hpp); "" for a solver without them or a scene without self-collision.
std::string describeSelfCollision(const Solver& solver);
// The CPU solvers' threads after a run: the substeps a team ran, and for a mid-sized cloth what its trial
// measured (cpu/team_trial.hpp); "" where one thread ran every substep by design.
std::string describeThreads(const Solver& solver);
// Where a CPU solver's team waited for its threads, by the line that waits, made with SolverRequest::record_waits;
// "" where not recorded (drape simulate --waits).
std::string describeWaits(const Solver& solver);

}  // namespace drape
