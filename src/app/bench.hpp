// `drape bench`: time each solver on each scene with its cloth resampled to N x N. Warm-up frames are
// not counted; each repeat times `frames` frames, and the median and spread are over repeats.
#pragma once

#include "app/measure.hpp"
#include "cpu/machine_peak.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace drape {

struct BenchOptions {
  std::vector<std::string> scenes = {"scenes/pinned2.json", "scenes/sphere.json"};
  std::vector<int> sizes = {32, 64, 128, 256};
  std::vector<std::string> solvers = {"cpu", "gpu"};
  std::vector<int> threads = {0};  // CPU solvers' thread counts, each a run of its own (0 = every core)
  bool team_always = false;        // CPU solvers: every substep on the team (SolverRequest::team_always)
  int frames = 5;                  // timed frames per repeat, at most
  int warmup = 2;                  // frames run first and not timed (GPU: programs, caches, first dispatches)
  int repeats = 3;                 // timed repeats; median and spread are over these
  double budget_s = 10;            // timed seconds per run: slow runs time fewer frames per repeat (at least 1)
  double peak_gbs = 0;             // the device's peak memory bandwidth; 0: from knownPeakGbs(renderer), if listed
  // Each of "verlet", "xpbd", "vbd" in turn replaces every scene's simulation.integrator, a run each; empty: as given.
  std::vector<std::string> integrators;
  bool keep_thickness = false;  // resampleCloth keeps each scene's thickness instead of capping it
  // A resampled scene beyond the stability bound gets the fewest substeps inside it (autoSubsteps, as
  // `simulate --auto-substeps`): a fine cloth at the scene's 30 blows up, and a blown-up run times nothing
  bool auto_substeps = false;
  bool roofline = false;  // probe this machine's peak first; the markdown adds each CPU pass's share of it
};

struct BenchPass {
  std::string name;
  double ms_per_frame = 0;     // mean over the timed frames
  double calls_per_frame = 0;  // invocations (CPU) or dispatches (GPU)
};

struct BenchRun {
  std::string scene;  // file as given
  std::string solver;
  std::string integrator;  // the scene's simulation.integrator as run: "verlet", "xpbd" or "vbd"
  int threads = 0;         // CPU solvers: OpenMP threads; 0 for the GPU
  int size = 0;            // N: the cloth is N x N
  long long points = 0;
  int steps_per_frame = 0;
  int frames_per_repeat = 0;  // after the budget
  std::string skipped;        // why it did not run; empty when it ran
  std::string blew_up;        // "frame F: what happened" when the state became non-finite or ran away
  Spread frame_ms;            // over repeats: wall milliseconds per frame
  std::vector<double> repeat_ms;
  std::vector<BenchPass> passes;
  std::string pass_timing;  // how the passes were timed
  double vertex_substeps_per_s = 0;
  int dispatches_per_frame = 0;       // 0 for CPU solvers
  double dispatches_per_substep = 0;  // GPU: Solver::dispatchesPerSubstep (1/substeps on the one-dispatch path)
  // Per timed frame, the loop's waits for the GPU besides the one glFinish per repeat that ends the clock
  // (gl::SyncCounts): read-backs and glFinish, then fence waits (the frame-late health check waiting for
  // the frame before). The loop checks health as the viewer does, every frame and a frame late.
  double sync_readbacks_per_frame = 0;
  double fence_waits_per_frame = 0;
  // GPU: the solver's traffic model (Solver::bytesPerPointPerSubstep), the bandwidth it implies at the
  // measured frame time, and that as a share of the device's peak (0 where the peak is not known).
  double bytes_per_point_substep = 0;
  double achieved_gbs = 0;
  double peak_share = 0;
  long long gpu_memory_bytes = -1;  // buffers the GPU solver allocated; -1 for CPU solvers
  double stability_limit = 0;       // the guard's limit for the scene's damping
  double stability_number = 0;      // dt sqrt(k_sum/m) of the resampled scene
  bool inside_bound = true;         // stability_number < the guard's limit (core/stability.hpp)
  // CPU float solvers: the grid kernels' instruction set ("" on the general path), the threads a substep's
  // team had, and the self-collision lists at the end of the run: entries a point, rebuilds a substep.
  std::string grid_kernels;
  int team_threads = 0;
  double team_share = 0;      // the share of the substeps that ran on the team (a mid-sized cloth's trial decides)
  double team_over_solo = 0;  // the trial's last measured team time over one thread's (0: no trial or no probe)
  double pair_entries_per_point = 0;
  double rebuilds_per_substep = 0;
  // The grid path kept the points in its padded arrays through the substeps (CpuSolver::keepsPointsInArrays):
  // integrate ran inside the forces' sweep, and nothing was copied in or back around the stretch limit
  bool points_in_arrays = false;
  // CPU solvers: the process's CPU time over the timed frames' wall time (all threads; below the thread
  // count where other work on the machine took the cores). 0 where not measured.
  double cpu_share = 0;
  // What the roofline's work model needs of the scene.
  int spheres = 0, planes = 0, stretch_passes = 1, iterations = 1;
};

struct BenchReport {
  std::string started_at;
  double wall_s = 0;
  MachineInfo machine;             // load_average as the run started
  std::string load_at_end;         // load average as it ended
  std::optional<GlInfo> gl;        // when a GPU solver ran
  double peak_gbs = 0;             // what peak_share is a share of: --peak-gbs, else knownPeakGbs(gl->renderer)
  std::vector<MachinePeak> peaks;  // --roofline: measured with 1 thread, then with the most threads asked for
  BenchOptions options;
  std::vector<BenchRun> runs;
};

// progress receives one line per run as it ends (the command prints it on stderr).
BenchReport runBench(const BenchOptions& options, const std::function<void(const std::string&)>& progress = {});
BenchRun benchOne(SolverFactory& factory, const Scene& scene, const std::string& scene_name, int size,
                  const std::string& solver, const BenchOptions& options, int threads = 0);

// Peak memory bandwidth (GB/s, the vendors' data sheets) of a few GPUs, by a name in their GL renderer
// string; 0 for any other (llvmpipe included: its "device memory" is the CPU's).
double knownPeakGbs(const std::string& renderer);

nlohmann::json benchJson(const BenchReport& report);
std::string benchMarkdown(const BenchReport& report);

// The runs of a `drape bench --json` file (this binary's or an earlier one's): scene, solver, threads,
// size, frame times and passes. Throws std::runtime_error naming the run and key that is missing or
// of the wrong type.
std::vector<BenchRun> benchRunsFromJson(const nlohmann::json& j);
// Before and after, per pass and per frame: every run of `after` against the run of `before` with the
// same scene (file name), size and solver, the same thread count where `before` has it (an earlier
// binary without --threads ran one thread). `before_label` names the baseline in the text.
std::string benchComparisonMarkdown(const BenchReport& after, const std::vector<BenchRun>& before,
                                    const std::string& before_label);
std::string describeRun(const BenchRun& run);  // the progress line

}  // namespace drape
