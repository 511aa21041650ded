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
  const Scene scene = resampleCloth(original, size, o.keep_thickness);
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
    solver = factory.make(scene, solver_name, {.threads = threads});
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

namespace {

nlohmann::json spreadJson(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}, {"q1", s.q1}, {"q3", s.q3}, {"samples", s.samples}};
}

}  // namespace

nlohmann::json benchJson(const BenchReport& r) {
  nlohmann::json j;
  j["tool"] = "drape bench";
  j["started_at"] = r.started_at;
  j["wall_s"] = r.wall_s;
  j["machine"] = {{"hostname", r.machine.hostname},
                  {"cpu_model", r.machine.cpu_model},
                  {"logical_cores", r.machine.logical_cores},
                  {"memory_bytes", r.machine.memory_bytes},
                  {"kernel", r.machine.kernel},
                  {"load_average_at_start", r.machine.load_average},
                  {"load_average_at_end", r.load_at_end}};
  if (r.gl)
    j["gl"] = {{"vendor", r.gl->vendor},
               {"renderer", r.gl->renderer},
               {"version", r.gl->version},
               {"glsl_version", r.gl->glsl_version},
               {"platform", r.gl->platform},
               {"software_renderer", r.gl->software},
               {"timer_queries", r.gl->timer_queries}};
  else
    j["gl"] = nullptr;
  j["peak_gbs"] = r.peak_gbs > 0 ? nlohmann::json(r.peak_gbs) : nlohmann::json(nullptr);
  j["cpu_peaks"] = peaksJson(r.peaks);  // --roofline's probes
  j["settings"] = {
      {"scenes", r.options.scenes},
      {"sizes", r.options.sizes},
      {"solvers", r.options.solvers},
      {"max_frames_per_repeat", r.options.frames},
      {"budget_s_per_run", r.options.budget_s},
      {"warmup_frames", r.options.warmup},
      {"repeats", r.options.repeats},
      {"cpu_threads", r.options.threads},
      {"keep_thickness", r.options.keep_thickness},
      {"integrators", r.options.integrators.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.options.integrators)}};
  j["runs"] = nlohmann::json::array();
  for (const BenchRun& run : r.runs) {
    nlohmann::json o = {{"scene", run.scene},
                        {"solver", run.solver},
                        {"integrator", run.integrator},
                        {"threads", run.threads},
                        {"size", run.size},
                        {"frames_per_repeat", run.frames_per_repeat},
                        {"points", run.points},
                        {"steps_per_frame", run.steps_per_frame},
                        {"stability_number", run.stability_number},
                        {"stability_limit", run.stability_limit},
                        {"inside_stability_bound", run.inside_bound}};
    if (!run.skipped.empty()) {
      o["skipped"] = run.skipped;
      j["runs"].push_back(o);
      continue;
    }
    o["blew_up"] = run.blew_up.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.blew_up);
    o["frame_ms"] = spreadJson(run.frame_ms);
    o["repeat_ms"] = run.repeat_ms;
    o["vertex_substeps_per_s"] = run.vertex_substeps_per_s;
    o["dispatches_per_frame"] = run.dispatches_per_frame;
    o["dispatches_per_substep"] = run.dispatches_per_substep;
    o["sync_readbacks_per_frame"] = run.sync_readbacks_per_frame;
    o["fence_waits_per_frame"] = run.fence_waits_per_frame;
    o["bytes_per_point_substep"] = run.bytes_per_point_substep;
    o["achieved_gbs"] = run.achieved_gbs;
    o["peak_share"] = run.peak_share > 0 ? nlohmann::json(run.peak_share) : nlohmann::json(nullptr);
    o["gpu_memory_bytes"] = run.gpu_memory_bytes >= 0 ? nlohmann::json(run.gpu_memory_bytes) : nlohmann::json(nullptr);
    o["pass_timing"] = run.pass_timing;
    if (!isGpuSolver(run.solver))
      o["cpu"] = {{"grid_kernels", run.grid_kernels},
                  {"team_threads", run.team_threads},
                  {"pair_entries_per_point", run.pair_entries_per_point},
                  {"rebuilds_per_substep", run.rebuilds_per_substep},
                  {"cpu_share", run.cpu_share}};
    o["passes"] = nlohmann::json::array();
    for (const BenchPass& p : run.passes)
      o["passes"].push_back(
          {{"name", p.name}, {"ms_per_frame", p.ms_per_frame}, {"calls_per_frame", p.calls_per_frame}});
    j["runs"].push_back(o);
  }
  return j;
}

std::string benchMarkdown(const BenchReport& r) {
  std::string gpu_label = "not run";
  if (r.gl)
    gpu_label = r.gl->software
                    ? fmt::format("{} (software rasteriser on the CPU cores: not GPU performance)", r.gl->renderer)
                    : r.gl->renderer;
  std::string md = fmt::format(
      "Machine: {} ({} logical cores, {:.0f} GiB; load average {} at the start, {} at the end). GPU solver: {}. "
      "CPU solvers: threads as shown after the solver's name.\n"
      "{} warm-up frames, then {} repeats of up to {} frames (fewer where a run would take over {:g} s); ms/frame is "
      "the median over repeats [min, max]. GPU rows: read-backs/frame counts the loop's waits for the GPU "
      "(docs/design.md, section 4); bytes/point/substep is the solver's traffic model, GB/s that model at the "
      "median frame time{}.\n\n",
      r.machine.cpu_model, r.machine.logical_cores, double(r.machine.memory_bytes) / (1024.0 * 1024.0 * 1024.0),
      r.machine.load_average, r.load_at_end, gpu_label, r.options.warmup, r.options.repeats, r.options.frames,
      r.options.budget_s,
      r.peak_gbs > 0 ? fmt::format(", in brackets as a share of the device's peak of {:g} GB/s", r.peak_gbs) : "");
  md +=
      "| scene | N×N | solver | substeps/frame | ms/frame | vertex-substeps/s | dispatches/substep | dispatches/frame "
      "| read-backs/frame | bytes/point/substep | GB/s (share of peak) | GPU memory | note |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BenchRun& run : r.runs) {
    const std::string scene = std::filesystem::path(run.scene).stem().string();
    std::string solver = run.solver;
    if (isGpuSolver(run.solver) && r.gl && r.gl->software) solver += " (llvmpipe)";
    if (run.threads > 0) solver += fmt::format(" ×{}", run.threads);
    if (run.integrator != "verlet") solver += ", " + run.integrator;
    if (!run.skipped.empty()) {
      md += fmt::format("| {} | {} | {} | {} | – | – | – | – | – | – | – | – | skipped: {} |\n", scene, run.size,
                        solver, run.steps_per_frame, run.skipped);
      continue;
    }
    std::string note;
    if (!run.blew_up.empty()) note = "blew up at " + run.blew_up;
    if (!run.inside_bound)
      note += fmt::format("{}beyond the stability bound ({:.2f} >= {:.2f})", note.empty() ? "" : "; ",
                          run.stability_number, run.stability_limit);
    const std::string ms = run.frame_ms.samples > 0 ? fmt::format("{:.2f} [{:.2f}, {:.2f}]", run.frame_ms.median,
                                                                  run.frame_ms.min, run.frame_ms.max)
                                                    : "–";
    const std::string rate = run.frame_ms.samples > 0 ? fmt::format("{:.3g}", run.vertex_substeps_per_s) : "–";
    const std::string mem =
        run.gpu_memory_bytes >= 0 ? fmt::format("{:.1f} MiB", double(run.gpu_memory_bytes) / (1024.0 * 1024.0)) : "–";
    const bool gpu = isGpuSolver(run.solver);
    // A fraction where one dispatch runs a frame's substeps: 1/30, not 0.0333.
    const std::string per_substep = !gpu                              ? "–"
                                    : run.dispatches_per_substep >= 1 ? fmt::format("{:g}", run.dispatches_per_substep)
                                                                      : fmt::format("1/{}", run.steps_per_frame);
    const std::string dispatches = gpu ? std::to_string(run.dispatches_per_frame) : "–";
    const std::string readbacks = gpu ? fmt::format("{:.2g}", run.sync_readbacks_per_frame) : "–";
    const std::string bytes = gpu ? fmt::format("{:.0f}", run.bytes_per_point_substep) : "–";
    std::string gbs = gpu && run.achieved_gbs > 0 ? fmt::format("{:.3g}", run.achieved_gbs) : "–";
    if (run.peak_share > 0) gbs += fmt::format(" ({:.1f}%)", 100 * run.peak_share);
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", scene, run.size, solver,
                      run.steps_per_frame, ms, rate, per_substep, dispatches, readbacks, bytes, gbs, mem, note);
  }
  return md;
}

namespace {

// An object of a baseline file (a run, its frame_ms): every value the comparison reads, checked for type
// and range, so that a hand-edited or foreign file is refused naming the key that is wrong instead of
// compared as garbage.
class BaselineObject {
 public:
  BaselineObject(const nlohmann::json& o, std::string where) : o_(o), where_(std::move(where)) {
    if (!o.is_object()) throw std::runtime_error(where_ + ": not an object");
  }

  bool has(const char* key) const { return o_.contains(key); }

  std::string text(const char* key, const char* otherwise = nullptr) const {
    if (!has(key) && otherwise) return otherwise;
    if (!has(key) || !o_[key].is_string()) fail(key, "missing or not a string");
    return o_[key].get<std::string>();
  }

  // An integer in [lo, hi]; `otherwise` when absent (required when there is none).
  int integer(const char* key, long long lo, long long hi, std::optional<int> otherwise = std::nullopt) const {
    if (!has(key) && otherwise) return *otherwise;
    if (!has(key) || !o_[key].is_number_integer()) fail(key, "missing or not an integer");
    const nlohmann::json& v = o_[key];
    // nlohmann keeps a non-negative literal unsigned, a negative one signed.
    const bool in_range = v.is_number_unsigned() ? v.get<std::uint64_t>() >= std::uint64_t(std::max(lo, 0LL)) &&
                                                       v.get<std::uint64_t>() <= std::uint64_t(hi)
                                                 : v.get<std::int64_t>() >= lo && v.get<std::int64_t>() <= hi;
    if (!in_range) fail(key, fmt::format("{} is out of range ({} to {})", v.dump(), lo, hi));
    return int(v.get<std::int64_t>());
  }

  // A number >= 0 (times, counts per frame); `otherwise` when absent.
  double amount(const char* key, std::optional<double> otherwise = std::nullopt) const {
    if (!has(key) && otherwise) return *otherwise;
    if (!has(key) || !o_[key].is_number()) fail(key, "missing or not a number");
    const double v = o_[key].get<double>();
    if (!(v >= 0) || !std::isfinite(v)) fail(key, fmt::format("{} is not a number >= 0", o_[key].dump()));
    return v;
  }

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    throw std::runtime_error(where_ + "." + key + ": " + problem);
  }

 private:
  const nlohmann::json& o_;
  std::string where_;
};

}  // namespace

std::vector<BenchRun> benchRunsFromJson(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("runs") || !j["runs"].is_array())
    throw std::runtime_error("\"runs\": missing, or not an array (not a drape bench --json file)");
  std::vector<BenchRun> runs;
  for (std::size_t k = 0; k < j["runs"].size(); ++k) {
    const std::string where = fmt::format("runs[{}]", k);
    const BaselineObject o(j["runs"][k], where);
    BenchRun run;
    run.scene = o.text("scene");
    run.solver = o.text("solver");
    run.integrator = o.text("integrator", "verlet");  // older files have none: Verlet was the only one
    run.size = o.integer("size", 2, 2048);
    run.threads = o.integer("threads", 0, 1024, 0);
    if (o.has("skipped")) run.skipped = o.text("skipped");
    if (o.has("frame_ms")) {
      const BaselineObject frame(j["runs"][k]["frame_ms"], where + ".frame_ms");
      run.frame_ms.median = frame.amount("median");
      run.frame_ms.samples = frame.integer("samples", 0, 1000000, 1);
    }
    if (o.has("passes")) {
      const nlohmann::json& passes = j["runs"][k]["passes"];
      if (!passes.is_array()) o.fail("passes", "not an array");
      for (std::size_t p = 0; p < passes.size(); ++p) {
        const BaselineObject pass(passes[p], fmt::format("{}.passes[{}]", where, p));
        run.passes.push_back({pass.text("name"), pass.amount("ms_per_frame"), pass.amount("calls_per_frame", 0.0)});
      }
    }
    runs.push_back(std::move(run));
  }
  return runs;
}

namespace {

const BenchRun* matchingRun(const std::vector<BenchRun>& runs, const BenchRun& run) {
  const std::string stem = std::filesystem::path(run.scene).stem().string();
  const BenchRun* any = nullptr;
  for (const BenchRun& b : runs) {
    if (std::filesystem::path(b.scene).stem().string() != stem || b.size != run.size || b.solver != run.solver ||
        !b.skipped.empty() || b.frame_ms.samples == 0)
      continue;
    if (b.threads == run.threads) return &b;
    if (b.threads == 0 && !any) any = &b;
  }
  return any;
}

std::string ratioCell(double before, double after) {
  return before > 0 ? fmt::format("{:.2f}", after / before) : "–";
}

}  // namespace

std::string benchComparisonMarkdown(const BenchReport& after, const std::vector<BenchRun>& before,
                                    const std::string& before_label) {
  std::string md = fmt::format(
      "Before ({}) and after (this run), ms per frame: medians over repeats for the frame, means over the timed "
      "frames for the passes. A pass missing on one side is \"–\".\n\n",
      before_label);
  md += "| scene | N×N | solver | pass | before | after | after / before |\n|---|---|---|---|---|---|---|\n";
  for (const BenchRun& run : after.runs) {
    if (!run.skipped.empty() || run.frame_ms.samples == 0) continue;
    const BenchRun* old = matchingRun(before, run);
    if (!old) continue;
    const std::string scene = std::filesystem::path(run.scene).stem().string();
    const std::string solver = run.threads > 0 ? fmt::format("{} ×{}", run.solver, run.threads) : run.solver;
    md += fmt::format("| {} | {} | {} | **frame** | {:.2f} | {:.2f} | **{}** |\n", scene, run.size, solver,
                      old->frame_ms.median, run.frame_ms.median, ratioCell(old->frame_ms.median, run.frame_ms.median));
    std::vector<std::string> names;
    for (const BenchPass& p : old->passes)
      names.push_back(p.name);
    for (const BenchPass& p : run.passes)
      if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
    for (const std::string& name : names) {
      double b = -1, a = -1;
      for (const BenchPass& p : old->passes)
        if (p.name == name) b = p.ms_per_frame;
      for (const BenchPass& p : run.passes)
        if (p.name == name) a = p.ms_per_frame;
      md += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", scene, run.size, solver, name,
                        b >= 0 ? fmt::format("{:.2f}", b) : "–", a >= 0 ? fmt::format("{:.2f}", a) : "–",
                        b >= 0 && a >= 0 ? ratioCell(b, a) : "–");
    }
  }
  return md;
}

}  // namespace drape
