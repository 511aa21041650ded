// `drape bench`'s report: the runs as JSON (and back, for --baseline), the markdown tables, the comparison
// with an earlier run. Kept apart from the running of the benchmarks (bench.cpp).
#include "app/bench.hpp"

#include "app/roofline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace drape {

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
      {"auto_substeps", r.options.auto_substeps},
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
      o["cpu"] = {
          {"grid_kernels", run.grid_kernels},
          {"points_in_arrays", run.points_in_arrays},
          {"team_threads", run.team_threads},
          {"team_share", run.team_share},
          {"team_over_solo", run.team_over_solo > 0 ? nlohmann::json(run.team_over_solo) : nlohmann::json(nullptr)},
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
    // A mid-sized cloth's trial ran some substeps on one thread: say how many ran on the team.
    if (run.threads > 1 && run.team_share > 0 && run.team_share < 1)
      solver += fmt::format(" (team {:.0f}%)", 100 * run.team_share);
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
