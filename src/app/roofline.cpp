#include "app/roofline.hpp"
#include "cpu/cpu_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace drape {

namespace {

// Springs of an N x N grid with every type enabled (docs/design.md section 2): structural, shearing, bending.
double gridSprings(double n) {
  return (2 * n * n - 2 * n) + 2 * (n - 1) * (n - 1) + (2 * n * n - 4 * n);
}

// Where the arrays a pass touches live: a cloth's state (positions, displacements, forces, the kernels' copies and
// rest lengths: about 128 bytes a point) stays in a core's L2 up to half of it (512 KiB where the system does not
// say), and in the L3 up to the L3 probe's arrays (12 MiB a thread) and half the L3 the system reports; beyond,
// it streams from memory.
constexpr double kCacheBytes = 512.0 * 1024;
constexpr double kL3ProbeBytesPerThread = 12.0 * 1024 * 1024;
constexpr double kStateBytesPerPoint = 128;

struct Ceiling {
  double gbs;
  const char* where;
};

Ceiling bandwidthFor(const MachinePeak& peak, const BenchRun& run) {
  const double state = double(run.points) * kStateBytesPerPoint;
  const double l2 = peak.l2_bytes > 0 ? 0.5 * double(peak.l2_bytes) : kCacheBytes;
  if (state <= l2 * std::max(1, run.team_threads)) return {peak.cache_gbs, "L2"};
  if (peak.l3_gbs > 0 && state <= 0.5 * double(peak.l3_bytes) &&
      state <= kL3ProbeBytesPerThread * std::max(1, run.team_threads))
    return {peak.l3_gbs, "L3"};
  return {peak.dram_gbs, "memory"};
}

const MachinePeak* peakFor(const BenchReport& r, const BenchRun& run) {
  if (r.peaks.empty()) return nullptr;
  return run.team_threads > 1 && r.peaks.size() > 1 ? &r.peaks[1] : &r.peaks[0];
}

}  // namespace

// What the roofline needs of a CPU run: the path it took and the self-collision lists' shape.
void recordCpuDetails(const Solver& solver, const Scene& scene, BenchRun& run) {
  run.spheres = int(scene.spheres.size());
  run.planes = int(scene.planes.size());
  run.stretch_passes = scene.sim.stretch_passes;
  run.iterations = scene.sim.iterations;
  if (const auto* cpu = dynamic_cast<const CpuSolver<float>*>(&solver)) {
    run.grid_kernels = cpu->gridKernels();
    // (with wind the forces take the general path, and integrate runs on its own)
    run.points_in_arrays = cpu->keepsPointsInArrays() && !scene.sim.wind.enabled;
    // A mid-sized cloth's trial may have run some substeps on one thread: the way most of them ran.
    run.team_threads = 2 * cpu->teamSubsteps() >= cpu->substeps() ? cpu->teamThreads() : 1;
    run.team_share = cpu->substeps() > 0 ? double(cpu->teamSubsteps()) / double(cpu->substeps()) : 0;
    if (const TeamTrial* trial = cpu->teamTrial(); trial && std::isfinite(trial->teamOverSolo()))
      run.team_over_solo = trial->teamOverSolo();
    if (cpu->substeps() > 0 && run.points > 0) {
      run.pair_entries_per_point = double(cpu->collisionPairs().pairCount()) / double(run.points);
      run.rebuilds_per_substep = double(cpu->collisionPairs().rebuilds()) / double(cpu->substeps());
    }
  }
}

nlohmann::json peaksJson(const std::vector<MachinePeak>& peaks) {
  nlohmann::json out = nlohmann::json::array();
  for (const MachinePeak& p : peaks)
    out.push_back({{"isa", p.isa},
                   {"threads", p.threads},
                   {"memory_gbs", p.dram_gbs},
                   {"l3_gbs", p.l3_gbs},
                   {"l2_bytes", p.l2_bytes},
                   {"l3_bytes", p.l3_bytes},
                   {"l2_gbs", p.cache_gbs},
                   {"addmul_gflops", p.addmul_gflops},
                   {"divsqrt_gops", p.divsqrt_gops},
                   {"barrier_us", p.barrier_us},
                   {"barrier_best_us", p.barrier_best_us},
                   {"omp_barrier_us", p.omp_barrier_us},
                   {"gap_share", p.gap_share},
                   {"gaps_per_second", p.gaps_per_second},
                   {"long_gaps_per_second", p.long_gaps_per_second}});
  return out;
}

std::optional<PassWork> passWork(const BenchRun& run, const std::string& pass) {
  const bool xpbd = run.integrator == "xpbd", vbd = run.integrator == "vbd";
  if ((run.integrator != "verlet" && !xpbd && !vbd) || run.solver != "cpu") return std::nullopt;
  const double n = run.size;
  const double ends = 2 * gridSprings(n) / (n * n);  // spring ends a point (12 inside the cloth)
  const bool grid = !run.grid_kernels.empty();
  if ((xpbd || vbd) && pass == "forces")
    // The prediction's forces: gravity times mass (3). Bytes: the mass read, the forces written.
    return PassWork{3, 0, 4 + 12};
  if (xpbd && pass == "xpbd_solve" && grid && run.iterations == 1) {
    // Per spring (xpbdSprings): d (3), |d|^2 (5), sqrt, len - rest (1), alpha 0 and its subtraction (2),
    // w_a + w_b + alpha (2), dlambda = / , s = dlambda / len, p = s d (3), -w_a p and w_b p (6), added to x and v
    // at both ends (12): 34 adds and multiplies, a square root and two divisions. Bytes: as the stretch limit's
    // (x and v copied in and back, the pin masks, six rest lengths) and the inverse masses (4).
    const double springs = gridSprings(n) / (n * n);
    return PassWork{34 * springs, 3 * springs, 96 + 28 + 4};
  }
  if (vbd && pass == "vbd_solve" && grid) {
    // A sweep visits every point once (vbdPoints). Per spring end (vbdAddSpring): d (3), |d|^2 (5), sqrt,
    // the force k (len - rest) / len d added (8 and a division), s = 1 - rest / len (1 and a division),
    // a = k (1 - s) / len^2 (3 and a division), b = k s (1), the Hessian's six terms (2 + 3 + 3 + 4 + 6):
    // 38 adds and multiplies, a square root and three divisions. Per point: m / dt^2 (1 and a division),
    // vbdStep's LDL^T solve (20 and six divisions), x and v moved (6); from the second sweep on, the inertia's
    // pull to the prediction (6). Bytes: as XPBD's sweep (x and v copied in and back, the pin masks, six rest
    // lengths, the inverse masses); several sweeps keep the prediction (12 written, 12 read a later sweep).
    // The gathers of a colour's scattered points are not modelled: the ratio to the roofline says what they cost.
    const double sweeps = std::max(1, run.iterations);
    return PassWork{sweeps * (38 * ends + 27) + (sweeps - 1) * 6, sweeps * (4 * ends + 7),
                    96 + 28 + 4 + (sweeps > 1 ? 12 * sweeps : 0)};
  }
  if ((xpbd || vbd) && pass != "integrate" && pass != "self_collide" && pass != "collide") return std::nullopt;
  if (pass == "forces" && grid && run.points_in_arrays)
    // As below, with integrate's work (15) in the same sweep: the positions read from the arrays (12), the mass
    // (4), six rest lengths (24), the forces written (12, read back from cache two rows later); integrate's
    // displacements read (12), positions and displacements written to the arrays and the vec3s (48), the pin
    // mask and 1/m (8).
    return PassWork{14 * ends + 3 + 15, ends, 12 + 4 + 24 + 12 + 12 + 48 + 8};
  if (pass == "integrate" && run.points_in_arrays) return std::nullopt;  // in the forces' sweep: a wait alone
  if (pass == "forces" && grid)
    // Per spring, once (springRow): d (3), |d|^2 (3 mul, 2 add), sqrt, len - rest, k (), / len; per spring
    // end (addSpring): d again (3), s d (3), f += (3); gravity times mass (3). Bytes: the positions read as
    // vec3s, written and read as arrays (12 + 12 + 12), the mass (4), six rest lengths (24), the forces
    // written (12); the springs' s and len stay in cache (three rows of them).
    return PassWork{14 * ends + 3, ends, 76};
  if (pass == "integrate")
    // f / m (3), a dt^2 (3), keep v (3), + (3), x + v (3). Bytes: pin (1), f, v, x read, v, x written, 1/m.
    return PassWork{15, 0, 1 + 12 * 5 + 4};
  if (pass == "self_collide") {
    // The travel check (3 sub, 3 mul, 2 add), each list entry's distance (the same 8), the average and the
    // correction added to x and v (10). Bytes: x and the anchor (24), the list (4 an entry), the correction
    // written and read (24), x and v read and written (48); the candidates' positions are gathered from cache.
    const double e = run.pair_entries_per_point;
    return PassWork{8 + 8 * e + 10, 0, 96 + 4 * e};
  }
  if (pass == "collide")
    // A sphere: x - c (3), |x - c| (5 and a sqrt); a plane: (x - p).n (8), v.n (5). The rare response is
    // left out. Bytes: pin, x and v read and written.
    return PassWork{8.0 * run.spheres + 13.0 * run.planes, double(run.spheres), 1 + 48};
  if (pass == "limit_stretch" && grid) {
    // A vector of springs all within the limit, most of them (99.6% on CS184's selfCollision, 92% on
    // pinned2): d (3), |d|^2 (5), limit rest (1), its square against |d|^2 (2). One with a spring over it also
    // takes the square root, two divisions and the corrections (19 more), which the count leaves out. Bytes: x
    // and v copied in and back (4 x 24), the pin masks (4) and six rest lengths (24); the colours' sweeps over
    // the copies stay in cache.
    const double springs = gridSprings(n) / (n * n) * run.stretch_passes;
    // Where the points stay in the arrays, nothing is copied: x and v read and written once by the sweeps
    return PassWork{11 * springs, 0, (run.points_in_arrays ? 48.0 : 96.0) + 28};
  }
  return std::nullopt;
}

std::string rooflineMarkdown(const BenchReport& r) {
  if (r.peaks.empty()) return "";
  std::string md = "## Roofline\n\n";
  md += fmt::format(
      "Ceilings measured on this machine just before the runs ({} vectors, the grid kernels' instructions; "
      "load average {} at the start). Triad: STREAM's a = b + s c, 12 bytes an element, over 3 × 64 MiB "
      "(memory), 3 × 4 MiB a thread (L3, past a core's L2) and 3 × 64 KiB a thread (L2). Adds and multiplies without "
      "fused multiply-add (the bits "
      "forbid it). A barrier: one barrier of the team (cpu/parallel.hpp's TeamBarrier), what each pass boundary of "
      "a substep costs, and an OpenMP barrier's median beside it (libgomp's, with a system call each). Time taken: "
      "the share of a running thread's wall clock lost in gaps of 1 µs or more between two reads of the clock "
      "(the threads at once), and such gaps a second a thread, all and of 16 µs or more: time a virtual machine's "
      "host takes unseen, which a team pays for every thread (a stall of one holds the others at the next "
      "barrier).\n\n",
      r.peaks.front().isa, r.machine.load_average);
  md +=
      "| threads | memory GB/s | L3 GB/s | L2 GB/s | add+mul GFLOP/s | div+sqrt G/s | barrier µs (median, best; "
      "OpenMP's) | time taken (share; gaps/s, of ≥ 16 µs) |\n|---|---|---|---|---|---|---|---|\n";
  for (const MachinePeak& p : r.peaks)
    md += fmt::format(
        "| {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.2f} | {} | {:.1f}%; {:.0f}, {:.0f} |\n", p.threads, p.dram_gbs,
        p.l3_gbs, p.cache_gbs, p.addmul_gflops, p.divsqrt_gops,
        p.threads > 1 ? fmt::format("{:.2f}, {:.2f}; {:.2f}", p.barrier_us, p.barrier_best_us, p.omp_barrier_us) : "–",
        100 * p.gap_share, p.gaps_per_second, p.long_gaps_per_second);
  md +=
      "\nPer pass, the work a point and call counted from the code (app/roofline.cpp says what each number "
      "holds), the least time a point the ceilings allow (the binding ceiling in brackets: memory, L3 or L2 "
      "bandwidth by where the cloth's state fits (about 128 bytes a point: L2 up to half the L2 the system "
      "reports, L3 up to the L3 probe's arrays and half the reported L3), add+mul or div+sqrt throughput), the "
      "measured time, and "
      "their ratio: the share of the roofline the pass reaches. Self-collision: list entries a point and "
      "rebuilds a substep at the end of the run; a rebuild's work is not in the model. A one-thread run's "
      "pass times are wall clock times the run's CPU share (its CPU time over its wall time, in brackets after "
      "the solver): the time it had a core, where other work on the machine took it now and then. The probes "
      "of one thread count CPU time too; a team's are wall clock.\n\n";
  md +=
      "| scene | N×N | solver | pass | add+mul | div+sqrt | bytes | least ns/point | measured ns/point | share |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BenchRun& run : r.runs) {
    const MachinePeak* peak = peakFor(r, run);
    if (!peak || run.passes.empty() || run.points <= 0) continue;
    const Ceiling memory = bandwidthFor(*peak, run);
    const std::string scene = std::filesystem::path(run.scene).stem().string();
    std::string solver = fmt::format("{} ×{}", run.solver, run.threads);
    if (!run.grid_kernels.empty()) solver += " " + run.grid_kernels;
    // One thread: its wall time less the time it waited for a core (spread over the passes as evenly as the
    // scheduler's ticks fall). A team's threads also wait for each other, which is the passes' own cost.
    const double on_core = run.team_threads <= 1 && run.cpu_share > 0 && run.cpu_share < 1 ? run.cpu_share : 1;
    if (on_core < 1) solver += fmt::format(" ({:.0f}% on a core)", 100 * on_core);
    for (const BenchPass& pass : run.passes) {
      const std::optional<PassWork> w = passWork(run, pass.name);
      if (!w || pass.calls_per_frame <= 0) continue;
      const double measured = on_core * pass.ms_per_frame * 1e6 / (pass.calls_per_frame * double(run.points));
      const std::pair<double, const char*> bounds[] = {{w->bytes / memory.gbs, memory.where},
                                                       {w->addmul / peak->addmul_gflops, "add+mul"},
                                                       {w->divsqrt / peak->divsqrt_gops, "div+sqrt"}};
      const auto& [least, kind] = *std::max_element(std::begin(bounds), std::end(bounds),
                                                    [](const auto& a, const auto& b) { return a.first < b.first; });
      std::string name = pass.name;
      if (pass.name == "forces" && run.points_in_arrays) name += " (with integrate)";
      if (pass.name == "self_collide")
        name += fmt::format(" ({:.1f} entries, {:.2f} rebuilds)", run.pair_entries_per_point, run.rebuilds_per_substep);
      md += fmt::format("| {} | {} | {} | {} | {:.0f} | {:.0f} | {:.0f} | {:.2f} ({}) | {:.2f} | {:.0f}% |\n", scene,
                        run.size, solver, name, w->addmul, w->divsqrt, w->bytes, least, kind, measured,
                        100 * least / measured);
    }
  }
  return md;
}

}  // namespace drape
