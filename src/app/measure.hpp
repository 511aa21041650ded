// What `drape bench`, `drape accuracy` and `drape stability` share: making the solvers they compare
// (with one headless GL context for every GPU solver), resampling a scene's cloth, the machine's
// description, order statistics of timings.
#pragma once

#include "core/scene.hpp"
#include "core/solver.hpp"

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

namespace gl {
class HeadlessContext;
}

// The solvers the measurement commands know:
//   "cpu"        CpuSolver<float>, displacement form (the GPU's arithmetic)
//   "cpu-xprev"  CpuSolver<float>, x_prev form (CS184's; measured for its round-off)
//   "cpu64"      CpuSolver<double>
//   "gpu"        GpuSolver on a headless EGL context
inline const std::vector<std::string> kMeasuredSolvers = {"cpu", "cpu-xprev", "cpu64", "gpu"};

// A solver that cannot run here (no GL 4.5 context, a grid beyond the GPU's limits): the run is
// recorded as skipped with this reason.
class SkippedRun : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GlInfo {
  std::string vendor, renderer, version, glsl_version, platform;
  bool software = false;       // llvmpipe and friends: timings are the CPU's, never the GPU's
  bool timer_queries = false;  // GL_TIME_ELAPSED works; otherwise passes are timed by glFinish + wall clock
};

// Makes solvers by name. The first "gpu" request creates one headless context that stays current for
// every later GPU solver; the factory must outlive the solvers it made.
class SolverFactory {
 public:
  SolverFactory();
  ~SolverFactory();
  SolverFactory(const SolverFactory&) = delete;
  SolverFactory& operator=(const SolverFactory&) = delete;

  // Throws SkippedRun when the solver cannot run here, CommandError(kExitBadInput) for an unknown name.
  // threads: the CPU solvers' OpenMP threads (0 = every core).
  std::unique_ptr<Solver> make(const Scene& scene, const std::string& name, bool pass_timing = false, int threads = 0);
  // Set once a GPU solver was made.
  const GlInfo* glInfo() const { return gl_info_.renderer.empty() ? nullptr : &gl_info_; }

 private:
  std::unique_ptr<gl::HeadlessContext> context_;
  std::string gpu_unavailable_;  // why no context could be made, once tried
  GlInfo gl_info_;
};

// The scene with its cloth resampled to n x n points: width, height and density (kg/m^2, so the
// total mass) stay, pins keep their relative grid place (corners stay corners), and thickness is
// capped at 0.45 x spacing so that neighbours at rest are outside the self-collision range 2 x thickness.
Scene resampleCloth(const Scene& scene, int n);

struct MachineInfo {
  std::string hostname, cpu_model, kernel;
  int logical_cores = 0;
  long long memory_bytes = 0;
  std::string load_average;  // /proc/loadavg's 1, 5 and 15 minute figures when read: others' work on these cores
};
MachineInfo readMachineInfo();
std::string readLoadAverage();

// Order statistics of timing samples (linear interpolation between order statistics).
struct Spread {
  double median = 0, min = 0, max = 0, q1 = 0, q3 = 0;
  int samples = 0;
};
Spread summarize(std::vector<double> values);

// "2026-11-22T03:50:00Z"
std::string utcTimestamp();

// Comma-separated lists for the command-line options; a value outside the bounds is an error.
std::vector<int> parseIntList(const std::string& option, const std::string& text, int min_value,
                              int max_value = std::numeric_limits<int>::max());
std::vector<double> parseDoubleList(const std::string& option, const std::string& text,
                                    double max_value = std::numeric_limits<double>::max());
// An empty `allowed` accepts any non-empty name.
std::vector<std::string> parseNameList(const std::string& option, const std::string& text,
                                       const std::vector<std::string>& allowed);

}  // namespace drape
