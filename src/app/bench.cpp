#include "app/bench.hpp"

#include "app/option_values.hpp"
#include "app/roofline.hpp"
#include "core/stability.hpp"
#include "gl/objects.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <thread>

namespace drape {

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process so far (every thread), in milliseconds.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::vector<BenchPass> passesPerFrame(const Solver& solver, int frames) {
  std::vector<BenchPass> out;
  for (const PassTiming& t : solver.timings())
    if (t.calls > 0) out.push_back({t.name, t.ms / frames, double(t.calls) / frames});
  return out;
}

// The GPU's pass times come from a second solver with timing on: per-pass timing may stall the
// pipeline (glFinish where timer queries do not work), which must not leak into the frame times.
// One warm-up frame is enough here: the programs are already compiled and cached by the first solver.
std::vector<BenchPass> timeGpuPasses(SolverFactory& factory, const Scene& scene, const std::string& name, int warmup,
                                     int frames) {
  std::unique_ptr<Solver> solver = factory.make(scene, name, {.pass_timing = true});
  for (int f = 0; f < std::min(warmup, 1); ++f)
    solver->stepFrame();
  solver->finish();
  solver->resetTimings();
  for (int f = 0; f < frames; ++f)
    solver->stepFrame();
  solver->finish();
  return passesPerFrame(*solver, frames);
}

}  // namespace

BenchRun benchOne(SolverFactory& factory, const Scene& original, const std::string& scene_name, int size,
                  const std::string& solver_name, const BenchOptions& o, int threads) {
  const Scene resampled = resampleCloth(original, size, o.keep_thickness);
  const Scene scene = o.auto_substeps ? withStableSubsteps(resampled) : resampled;
  BenchRun run;
  run.scene = scene_name;
  run.solver = solver_name;
  run.integrator = integratorName(scene.sim.integrator);
  run.size = size;
  run.points = (long long)size * size;
  run.steps_per_frame = scene.sim.steps_per_frame;
  const StabilityCheck bound = checkStability(scene);
  run.stability_number = bound.number;
  run.stability_limit = bound.limit;
  run.inside_bound = bound.ok;

  std::unique_ptr<Solver> solver;
  try {
    solver = factory.make(scene, solver_name,
                          {.pass_timing = !isGpuSolver(solver_name),
                           .threads = threads,
                           .team_always = o.team_always && !isGpuSolver(solver_name)});
  } catch (const SkippedRun& e) {
    run.skipped = e.what();
    return run;
  }
  const bool gpu = isGpuSolver(solver_name);
  run.threads = solver->threads();
  int frame = 0;
  auto sane = [&] {
    const std::string why = solver->health().describe();
    if (!why.empty()) run.blew_up = fmt::format("frame {}: {}", frame, why);
    return why.empty();
  };
  // A blown-up state is not timed: NaNs change the arithmetic's speed and pile every point into one
  // hash cell. The CPU is checked every frame (outside the clock); the GPU after each repeat, because a
  // read-back per frame would add a pipeline stall that a real-time loop does not have.
  double last_warmup_ms = 0;
  for (int f = 0; f < o.warmup; ++f) {
    const auto start = Clock::now();
    solver->stepFrame();
    solver->finish();
    last_warmup_ms = msSince(start);
    ++frame;
    if (!gpu && !sane()) return run;
  }
  if (gpu && !sane()) return run;
  run.frames_per_repeat = o.frames;
  if (last_warmup_ms > 0) {
    const double affordable = o.budget_s * 1e3 / (o.repeats * last_warmup_ms);
    run.frames_per_repeat = std::clamp(int(affordable), 1, o.frames);
  }
  const int frames = run.frames_per_repeat;
  solver->resetTimings();
  int timed_frames = 0;
  long long waits = 0, fence_waits = 0;
  double wall_ms = 0, cpu_ms = 0;  // over every timed frame: the process's CPU time against the wall's
  for (int r = 0; r < o.repeats && run.blew_up.empty(); ++r) {
    double ms = 0;
    const double cpu_start = processCpuMs();
    const gl::SyncCounts before = gl::syncCounts();
    for (int f = 0; f < frames; ++f) {
      const auto start = Clock::now();
      solver->stepFrame();
      // What a real-time loop does on the GPU: the health check a frame late, which waits for nothing.
      if (gpu && !solver->recentHealth().ok() && run.blew_up.empty()) run.blew_up = fmt::format("frame {}", frame);
      if (gpu && f + 1 == frames) solver->finish();
      ms += msSince(start);
      ++frame;
      if (!gpu && !sane()) break;
    }
    const gl::SyncCounts after = gl::syncCounts();
    waits += after.readbacks - before.readbacks + after.finishes - before.finishes - (gpu ? 1 : 0);
    fence_waits += after.fence_waits - before.fence_waits;
    if (gpu) sane();
    if (!run.blew_up.empty()) break;
    cpu_ms += processCpuMs() - cpu_start;
    wall_ms += ms;
    run.repeat_ms.push_back(ms / frames);
    timed_frames += frames;
  }
  run.frame_ms = summarize(run.repeat_ms);
  if (gpu) run.bytes_per_point_substep = solver->bytesPerPointPerSubstep();
  if (gpu && run.frame_ms.samples > 0 && run.frame_ms.median > 0)
    run.achieved_gbs =
        run.bytes_per_point_substep * double(run.points) * run.steps_per_frame / (run.frame_ms.median * 1e-3) / 1e9;
  if (timed_frames > 0) {
    run.sync_readbacks_per_frame = double(waits) / timed_frames;
    run.fence_waits_per_frame = double(fence_waits) / timed_frames;
  }
  if (run.frame_ms.samples > 0 && run.frame_ms.median > 0)
    run.vertex_substeps_per_s = double(run.points) * run.steps_per_frame / (run.frame_ms.median * 1e-3);
  run.dispatches_per_frame = solver->dispatchesPerFrame();
  run.dispatches_per_substep = gpu ? solver->dispatchesPerSubstep() : 0;
  run.gpu_memory_bytes = solver->deviceMemoryBytes();
  if (!gpu) {
    if (timed_frames > 0) run.passes = passesPerFrame(*solver, timed_frames);
    if (wall_ms > 0) run.cpu_share = cpu_ms / wall_ms;
    recordCpuDetails(*solver, scene, run);
    run.pass_timing = fmt::format("wall clock per pass, {} thread{}", run.threads, run.threads == 1 ? "" : "s");
  } else if (run.blew_up.empty()) {
    solver.reset();
    run.passes = timeGpuPasses(factory, scene, solver_name, o.warmup, frames);
    const GlInfo* gl = factory.glInfo();
    run.pass_timing = gl && gl->timer_queries ? "GL timer queries" : "wall clock around glFinish per pass";
  }
  return run;
}

std::string describeRun(const BenchRun& r) {
  std::string head =
      fmt::format("{} {}x{} {}", std::filesystem::path(r.scene).stem().string(), r.size, r.size, r.solver);
  if (r.integrator != "verlet") head += " " + r.integrator;
  if (r.threads > 0) head += fmt::format(" ({} thread{})", r.threads, r.threads == 1 ? "" : "s");
  if (!r.skipped.empty()) return head + ": skipped (" + r.skipped + ")";
  std::string line = head;
  if (r.frame_ms.samples > 0)
    line += fmt::format(": {:.3f} ms/frame (min {:.3f}, max {:.3f}), {:.3g} vertex-substeps/s", r.frame_ms.median,
                        r.frame_ms.min, r.frame_ms.max, r.vertex_substeps_per_s);
  if (!r.blew_up.empty()) line += ": blew up at " + r.blew_up;
  if (!r.inside_bound)
    line += fmt::format(" [beyond the stability bound: {:.3g} >= {:.3g}]", r.stability_number, r.stability_limit);
  return line;
}

BenchReport runBench(const BenchOptions& o, const std::function<void(const std::string&)>& progress) {
  BenchReport report;
  report.started_at = utcTimestamp();
  report.machine = readMachineInfo();
  report.options = o;
  const auto start = Clock::now();
  std::vector<Scene> scenes;
  for (const std::string& path : o.scenes) {
    scenes.push_back(loadScene(path));  // all bad input fails first
    // --sizes resamples the grid; a mesh is the size its file gives.
    if (!scenes.back().cloth.isGrid())
      throw SceneError(path + ": cloth.mesh: bench resamples grid cloths to --sizes; a mesh cloth has no grid");
  }
  // "": the scene's own integrator.
  const std::vector<std::string> integrators = o.integrators.empty() ? std::vector<std::string>{""} : o.integrators;
  if (o.roofline) {
    const int most = std::max(1, *std::max_element(o.threads.begin(), o.threads.end()));
    report.peaks.push_back(measurePeak(1));
    if (most > 1 || o.threads.front() == 0)
      report.peaks.push_back(measurePeak(most > 1 ? most : int(std::max(1U, std::thread::hardware_concurrency()))));
  }
  SolverFactory factory({.skip_unavailable = true});
  std::size_t total = 0;
  for (const std::string& solver : o.solvers)
    total += o.scenes.size() * o.sizes.size() * integrators.size() * (isGpuSolver(solver) ? 1 : o.threads.size());
  for (std::size_t s = 0; s < scenes.size(); ++s)
    for (int size : o.sizes)
      for (const std::string& integrator : integrators) {
        Scene scene = scenes[s];
        applyIntegrator(scene, integrator);
        for (const std::string& solver : o.solvers)
          for (int threads : isGpuSolver(solver) ? std::vector<int>{0} : o.threads) {
            report.runs.push_back(benchOne(factory, scene, o.scenes[s], size, solver, o, threads));
            if (progress)
              progress(fmt::format("[{}/{}] {}", report.runs.size(), total, describeRun(report.runs.back())));
          }
      }
  if (const GlInfo* gl = factory.glInfo()) report.gl = *gl;
  report.peak_gbs = o.peak_gbs > 0 ? o.peak_gbs : report.gl ? knownPeakGbs(report.gl->renderer) : 0.0;
  if (report.peak_gbs > 0)
    for (BenchRun& run : report.runs)
      if (run.achieved_gbs > 0) run.peak_share = run.achieved_gbs / report.peak_gbs;
  report.wall_s = msSince(start) * 1e-3;
  report.load_at_end = readLoadAverage();
  return report;
}

double knownPeakGbs(const std::string& renderer) {
  // Longer names first: "H100 PCIe" before "H100".
  static const std::pair<const char*, double> kPeaks[] = {
      {"H200", 4800}, {"H100 PCIe", 2000}, {"H100", 3350},     {"A100-SXM4-80GB", 2039}, {"A100", 1555},
      {"L40S", 864},  {"L4", 300},         {"RTX 4090", 1008}, {"RTX 3090", 936},
  };
  for (const auto& [name, gbs] : kPeaks)
    if (renderer.find(name) != std::string::npos) return gbs;
  return 0;
}

}  // namespace drape
