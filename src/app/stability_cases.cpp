#include "app/stability_cases.hpp"
#include "app/jobs.hpp"
#include "app/progress.hpp"
#include "app/stability_summary.hpp"

#include "core/derived.hpp"
#include "core/hash.hpp"
#include "core/metrics.hpp"
#include "core/stability.hpp"
#include "cpu/cpu_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

namespace drape {

namespace {

// The scenes' cloth (1 m, 50 x 50 points, 150 kg/m^2, ks 5000 N/m, 0.2 % damping), held at its four
// corners, so that the largest stable ks applies to the shipped scenes; the soak uses a smaller one.
Scene baseScene(int n = 50) {
  Scene s;
  s.path = "stability";
  ClothSpec& c = s.cloth;
  c.num_width_points = n;
  c.num_height_points = n;
  c.density = 150.0;
  c.ks = 5000.0;
  c.damping = 0.2;
  c.thickness = 0.0095;
  c.pinned = {{0, 0}, {n - 1, 0}, {0, n - 1}, {n - 1, n - 1}};
  s.sim.self_collision = false;
  return s;
}

std::string decade(double v) {
  return fmt::format("1e{}", int(std::lround(std::log10(v))));
}

// Seeded value in [-1, 1] for point i and axis a, so every run starts identically.
double noise(std::uint32_t i, std::uint32_t a) {
  return double(hashU32(i * 3U + a + 0x5bd1e995U)) / 4294967295.0 * 2.0 - 1.0;
}

double gravityEnergy(const Scene& s, double mass, const Positions& x) {
  double e = 0;
  for (const glm::dvec3& p : x)
    e -= mass * glm::dot(s.sim.gravity, p);
  return e;
}

double springEnergy(const Topology& topo, const ClothSpec& c, const Positions& x) {
  double e = 0;
  for (const Spring& s : topo.springs) {
    if (!c.springEnabled(s.type)) continue;
    const double k = derived::springStiffness(c, s.type);
    const double stretch = glm::distance(x[s.a], x[s.b]) - s.rest;
    e += 0.5 * k * stretch * stretch;
  }
  return e;
}

}  // namespace

std::vector<StabilityCase> stabilityCases() {
  std::vector<StabilityCase> cases;
  for (double ks = 1e2; ks <= 1.01e7; ks *= 10) {
    StabilityCase c{"ks-" + decade(ks), fmt::format("ks = {:g} N/m, corners pinned", ks), baseScene()};
    c.scene.cloth.ks = ks;
    c.sweeps_ks = true;
    cases.push_back(c);
  }
  for (double density = 1; density <= 1.01e4; density *= 10) {
    StabilityCase c{"density-" + decade(density), fmt::format("density = {:g} kg/m^2, corners pinned", density),
                    baseScene()};
    c.scene.cloth.density = density;
    cases.push_back(c);
  }
  for (double damping : {0.0, 100.0}) {
    StabilityCase c{fmt::format("damping-{:g}", damping), fmt::format("damping = {:g} %", damping), baseScene()};
    c.scene.cloth.damping = damping;
    cases.push_back(c);
  }
  {
    StabilityCase c{"heavy-two-pins", "1000 kg/m^2 hanging from two corners", baseScene()};
    c.scene.cloth.density = 1000.0;
    c.scene.cloth.pinned = {{0, 0}, {49, 0}};
    cases.push_back(c);
  }
  {
    StabilityCase c{"jittered", "every free point moved up to 0.3 spacing per axis", baseScene()};
    c.start = StartState::Jittered;
    cases.push_back(c);
  }
  {
    StabilityCase c{"crumpled", "squeezed to 30 % and folded, no pins, floor, self-collision", baseScene()};
    c.scene.cloth.pinned.clear();
    c.scene.planes.push_back({glm::dvec3(0.0), glm::dvec3(0, 1, 0), 0.5});
    c.scene.sim.self_collision = true;
    c.start = StartState::Crumpled;
    cases.push_back(c);
  }
  {
    StabilityCase c{"sphere-strike", "free cloth moving at 20 m/s into a sphere", baseScene()};
    c.scene.cloth.pinned.clear();
    c.scene.spheres.push_back({glm::dvec3(0.5, 0.5, 0.5), 0.3, 0.3});
    c.start = StartState::Moving;
    c.start_velocity = glm::dvec3(0, -20, 0);
    cases.push_back(c);
  }
  // Beyond 1e7 Verlet needs thousands of substeps per frame (its bound grows as sqrt(ks)): XPBD only.
  for (double ks : {1e8, 1e9}) {
    StabilityCase c{"ks-" + decade(ks), fmt::format("ks = {:g} N/m, corners pinned (XPBD only)", ks), baseScene()};
    c.scene.cloth.ks = ks;
    c.implicit_only = true;
    cases.push_back(c);
  }
  {
    StabilityCase c{"soak-10000", "10,000 frames (111 s), 10 x 10, corners pinned", baseScene(10)};
    c.frames = 10000;
    cases.push_back(c);
  }
  return cases;
}

void startState(const StabilityCase& c, std::vector<glm::dvec3>& x, std::vector<glm::dvec3>& v) {
  const Topology topo = buildTopology(c.scene.cloth);
  x = topo.initial_positions;
  v.assign(x.size(), glm::dvec3(0));
  const ClothSpec& cloth = c.scene.cloth;
  const double spacing =
      std::min(cloth.width / (cloth.num_width_points - 1), cloth.height / (cloth.num_height_points - 1));
  const glm::dvec3 centre = centroid(x);
  for (std::uint32_t i = 0; i < x.size(); ++i) {
    if (topo.pinned[i]) continue;
    switch (c.start) {
      case StartState::Rest:
        break;
      case StartState::Jittered:
        x[i] += c.jitter * spacing * glm::dvec3(noise(i, 0), noise(i, 1), noise(i, 2));
        break;
      case StartState::Crumpled: {
        const glm::dvec3 d = x[i] - centre;
        x[i] = centre + c.crumple * glm::dvec3(d.x, 0, d.z);
        x[i].y += 0.1 * std::sin(9.0 * d.x) * std::cos(7.0 * d.z) + 0.02 * noise(i, 1);
        break;
      }
      case StartState::Moving:
        v[i] = c.start_velocity * c.scene.sim.dt();
        break;
    }
  }
}

StabilityResult runStabilityCase(const StabilityCase& c, int steps, bool guard, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  StabilityCase run = c;
  run.scene.sim.steps_per_frame = steps;
  StabilityResult r;
  r.case_name = c.name;
  r.integrator = c.scene.sim.integrator;
  r.steps_asked = steps;
  r.steps_per_frame = steps;
  // The guard does what `drape simulate --auto-substeps` does: raise the count, same losses per second.
  if (guard && run.scene.sim.integrator == Integrator::Verlet) {
    run.scene = withStableSubsteps(run.scene);
    r.steps_per_frame = run.scene.sim.steps_per_frame;
    r.guarded = r.steps_per_frame > steps;
  }
  const StabilityCheck bound = checkStability(run.scene);
  r.stability_number = bound.number;
  r.stability_limit = bound.limit;
  r.inside_bound = bound.ok;

  std::vector<glm::dvec3> x0, v0;
  startState(run, x0, v0);
  CpuSolver<float> solver(run.scene, CpuSolverOptions{.threads = threads});
  solver.setState(x0, v0);
  const Topology& topo = solver.topology();
  const double mass = derived::pointMass(run.scene.cloth), dt = run.scene.sim.dt();
  auto energy = [&](const Positions& x, double ke) {
    return ke + gravityEnergy(run.scene, mass, x) + springEnergy(topo, run.scene.cloth, x);
  };
  // The state the solver actually holds (float) is the start the energy and the blow-up test refer to.
  const Positions start = solver.readPositions();
  const double ke0 = kineticEnergy(solver.readDisplacements(), mass, dt);
  r.energy_start = r.energy_half = r.energy_end = energy(start, ke0);
  r.ke_max = r.ke_end = ke0;
  const double spring0 = springEnergy(topo, run.scene.cloth, start);
  for (int f = 1; f <= c.frames; ++f) {
    solver.stepFrame();
    r.frames_run = f;
    const Positions x = solver.readPositions();
    const std::string why = detectBlowUp(topo, run.scene.cloth, start, x);
    if (!why.empty()) {
      r.stable = false;
      r.first_bad_frame = f;
      r.what = why;
      break;
    }
    r.end_strain = maxStrain(topo, run.scene.cloth, x);
    r.max_strain = std::max(r.max_strain, r.end_strain);
    r.ke_end = kineticEnergy(solver.readDisplacements(), mass, dt);
    r.ke_max = std::max(r.ke_max, r.ke_end);
    if (f == c.frames / 2) r.energy_half = energy(x, r.ke_end);
    if (f == c.frames) r.energy_end = energy(x, r.ke_end);
  }
  const double weight = mass * double(topo.pointCount()) * glm::length(run.scene.sim.gravity);
  r.energy_scale = r.ke_max + weight * clothSize(run.scene.cloth) + spring0;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

std::string trend(const StabilityResult& r) {
  if (!r.stable) return "–";
  const double change = (r.energy_end - r.energy_start) / r.energy_scale;
  const char* word = change > 0.01 ? "grows" : change < -0.01 ? "decays" : "flat";
  return fmt::format("{} ({:+.2g})", word, change);
}

std::string describe(const StabilityResult& r) {
  std::string line = fmt::format("{} {}{} substeps{}: ", r.case_name,
                                 isImplicit(r.integrator) ? std::string(integratorName(r.integrator)) + " " : "",
                                 r.steps_per_frame, r.guarded ? " (guard)" : "");
  if (r.stable)
    line += fmt::format("stable, {}, max strain {:.3g}, end {:.3g}, KE end/max {:.2g}, energy {}",
                        keepsShape(r) ? "keeps its shape" : "OUT OF SHAPE", r.max_strain, r.end_strain,
                        r.ke_max > 0 ? r.ke_end / r.ke_max : 0.0, trend(r));
  else
    line += fmt::format("UNSTABLE at frame {}: {}", r.first_bad_frame, r.what);
  return line;
}

}  // namespace

StabilityReport runStability(const std::vector<StabilityCase>& cases, const std::vector<int>& steps,
                             const std::function<void(const std::string&)>& progress, int jobs,
                             const std::vector<int>& implicit_steps, const std::vector<Integrator>& implicit) {
  StabilityReport report;
  report.steps = steps;
  report.implicit_steps = implicit_steps;
  report.implicit = implicit_steps.empty() ? std::vector<Integrator>{} : implicit;
  const auto t0 = std::chrono::steady_clock::now();
  struct Job {
    const StabilityCase* c;
    int steps;
    bool guard;
  };
  std::vector<StabilityCase> xpbd_cases;
  xpbd_cases.reserve(cases.size() * report.implicit.size());
  for (Integrator integrator : report.implicit)
    for (const StabilityCase& c : cases) {
      xpbd_cases.push_back(c);
      xpbd_cases.back().scene.sim.integrator = integrator;
    }
  std::vector<Job> jobs_list;
  for (const StabilityCase& c : cases)
    for (int s : c.implicit_only ? std::vector<int>{} : steps) {
      jobs_list.push_back({&c, s, false});
      Scene probe = c.scene;
      probe.sim.steps_per_frame = s;
      if (autoSubsteps(probe) > s) jobs_list.push_back({&c, s, true});
    }
  for (const StabilityCase& c : xpbd_cases)
    for (int s : implicit_steps)
      jobs_list.push_back({&c, s, false});
  report.jobs = jobsFor(jobs, jobs_list.size());
  report.threads_per_run = threadsPerJob(report.jobs);
  report.results.resize(jobs_list.size());
  std::vector<double> cost;
  for (const Job& job : jobs_list)
    cost.push_back(stabilityRunCost(*job.c, job.steps, job.guard));
  SweepEstimate estimate(cost);
  std::mutex progress_mutex;
  forEachJob(jobs_list.size(), report.jobs, [&](std::size_t j) {
    const Job& job = jobs_list[j];
    report.results[j] = runStabilityCase(*job.c, job.steps, job.guard, report.threads_per_run);
    std::lock_guard<std::mutex> lock(progress_mutex);
    const std::string count = estimate.finished(j);
    if (progress) progress(count + ": " + describe(report.results[j]));
  });
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

std::string stabilityCsv(const StabilityReport& report) {
  std::string csv =
      "case,integrator,steps_asked,guard,steps_per_frame,stability_number,stability_limit,inside_bound,stable,keeps_"
      "shape,first_bad_frame,"
      "frames_run,"
      "max_strain,end_strain,ke_max_j,ke_end_j,energy_start_j,energy_end_j,energy_change_rel,wall_s,what\n";
  for (const StabilityResult& r : report.results) {
    const double change = r.stable ? (r.energy_end - r.energy_start) / r.energy_scale : NAN;
    csv += fmt::format(
        "{},{},{},{},{},{:.6g},{:.6g},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.9g},{},{},{:.3f},\"{}\"\n",
        r.case_name, integratorName(r.integrator), r.steps_asked, r.guarded ? 1 : 0, r.steps_per_frame,
        r.stability_number, r.stability_limit, r.inside_bound ? 1 : 0, r.stable ? 1 : 0, keepsShape(r) ? 1 : 0,
        r.first_bad_frame, r.frames_run, r.max_strain, r.end_strain, r.ke_max, r.ke_end, r.energy_start,
        r.stable ? fmt::format("{:.9g}", r.energy_end) : "", r.stable ? fmt::format("{:.4g}", change) : "", r.wall_s,
        r.what);
  }
  return csv;
}

const StabilityResult* findResult(const StabilityReport& report, const std::string& case_name, int steps_asked,
                                  bool guarded, Integrator integrator) {
  for (const StabilityResult& r : report.results)
    if (r.case_name == case_name && r.steps_asked == steps_asked && r.guarded == guarded && r.integrator == integrator)
      return &r;
  return nullptr;
}

namespace {

std::string shapeCell(const StabilityResult& r) {
  return keepsShape(r) ? "yes" : r.stable ? "**no**" : "–";
}

// The largest ks among the ks cases whose result passes `good`, and the smaller ones that do not (the sweep is
// not necessarily monotonic: the stretch limit and collisions are not covered by the bound).
template <class Pick, class Good>
std::string largestKs(const std::vector<StabilityCase>& cases, Pick pick, Good good) {
  double best = 0;
  for (const StabilityCase& c : cases)
    if (const StabilityResult* r = pick(c); r && good(*r)) best = std::max(best, c.scene.cloth.ks);
  std::vector<std::string> failing_below;
  for (const StabilityCase& c : cases)
    if (const StabilityResult* r = pick(c); r && !good(*r) && c.scene.cloth.ks < best)
      failing_below.push_back(fmt::format("{:g}", c.scene.cloth.ks));
  std::string cell = best > 0 ? fmt::format("{:g}", best) : "none";
  if (!failing_below.empty()) cell += fmt::format(" (but not {})", fmt::join(failing_below, ", "));
  return cell;
}

bool isStable(const StabilityResult& r) {
  return r.stable;
}

std::string markdownRow(const StabilityResult& r, const StabilityResult* guarded) {
  std::string guard = "inside bound";
  if (guarded)
    guard = fmt::format("{} substeps: {}", guarded->steps_per_frame,
                        guarded->stable ? "stable" : fmt::format("unstable (frame {})", guarded->first_bad_frame));
  else if (!r.inside_bound)
    guard = "no count inside the bound";
  const std::string bad = r.stable ? "–" : std::to_string(r.first_bad_frame);
  const std::string strain = r.stable ? fmt::format("{:.3g}", r.max_strain) : "–";
  const std::string end = r.stable ? fmt::format("{:.3g}", r.end_strain) : "–";
  const std::string ke = r.stable && r.ke_max > 0 ? fmt::format("{:.2g}", r.ke_end / r.ke_max) : "–";
  return fmt::format("| {} | {} | {:.3g} / {:.3g} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.case_name,
                     r.steps_per_frame, r.stability_number, r.stability_limit, r.stable ? "yes" : "**no**",
                     shapeCell(r), bad, strain, end, ke, trend(r), guard);
}

// An implicit integrator's runs: the same cases (and ks 1e8, 1e9) without any guard, with what each cost.
std::string implicitMarkdown(const StabilityReport& report, const std::vector<StabilityCase>& cases,
                             Integrator integrator) {
  const bool xpbd = integrator == Integrator::Xpbd;
  std::string md =
      fmt::format("\n{} (simulation.integrator {}, {}), the same cases without the guard, and ks 1e8 and 1e9:\n\n",
                  xpbd ? "XPBD" : "VBD", integratorName(integrator),
                  xpbd ? "1 sweep of the springs" : "1 sweep of per-point Newton steps");
  md +=
      "| case | substeps | stable | keeps shape | first bad frame | max strain | end strain | KE end / max | energy | "
      "run s |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const StabilityResult& r : report.results) {
    if (r.integrator != integrator) continue;
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1f} |\n", r.case_name, r.steps_per_frame,
                      r.stable ? "yes" : "**no**", shapeCell(r), r.stable ? "–" : std::to_string(r.first_bad_frame),
                      r.stable ? fmt::format("{:.3g}", r.max_strain) : "–",
                      r.stable ? fmt::format("{:.3g}", r.end_strain) : "–",
                      r.stable && r.ke_max > 0 ? fmt::format("{:.2g}", r.ke_end / r.ke_max) : "–", trend(r), r.wall_s);
  }
  md += fmt::format(
      "\nLargest ks (N/m, of 1e2..1e9) with {} that runs stable, and that keeps its shape (max strain <= {:g}%), per "
      "substep count:\n\n",
      xpbd ? "XPBD" : "VBD", 100 * kShapeStrain);
  md += "| substeps | stable | keeps its shape |\n|---|---|---|\n";
  for (int s : report.implicit_steps) {
    auto pick = [&](const StabilityCase& c) {
      return c.sweeps_ks || c.implicit_only ? findResult(report, c.name, s, false, integrator) : nullptr;
    };
    md += fmt::format("| {} | {} | {} |\n", s, largestKs(cases, pick, isStable), largestKs(cases, pick, keepsShape));
  }
  return md;
}

}  // namespace

std::string stabilityMarkdown(const StabilityReport& report, const std::vector<StabilityCase>& cases) {
  std::string md = fmt::format(
      "CPU float solver, 1 m cloth of 50 x 50 points (10 x 10 for the soak), 90 frames/s, 180 frames (2 s) per case "
      "unless stated; {:.0f} s in all ({} runs at a time, {} solver thread{} each). Unstable: a non-finite coordinate, "
      "a spring beyond 11x its rest length, or a "
      "point more than 100 cloth sizes from its start. Keeps its shape: stable, and no spring ever stretched more "
      "than {:g}%. Max strain: the largest in any frame; end strain: at the last frame. Guard: dt*sqrt(k_sum/m) < "
      "sqrt(1 + keep), keep = 1 - "
      "damping/100 "
      "(sqrt(2) = {:.4g} undamped, 1 at 100 % damping); with the guard the substeps "
      "are raised to the smallest count inside it, with damping and friction rescaled to the same loss per second (as "
      "`drape simulate --auto-substeps` does). Energy: kinetic + gravitational + spring, change from start to end "
      "relative to the largest of them.\n\n",
      report.wall_s, report.jobs, report.threads_per_run, report.threads_per_run == 1 ? "" : "s", 100 * kShapeStrain,
      kStabilityLimit);
  md +=
      "| case | substeps | dt·sqrt(k/m) / limit | stable | keeps shape | first bad frame | max strain | end strain | "
      "KE "
      "end / max |";
  md += " energy | with guard |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const StabilityResult& r : report.results)
    if (!r.guarded && r.integrator == Integrator::Verlet)
      md += markdownRow(r, findResult(report, r.case_name, r.steps_asked, true));

  md += fmt::format(
      "\nLargest ks (N/m, of 1e2..1e7) that runs stable, and that keeps its shape (max strain <= {:g}%), per substep "
      "count:\n\n",
      100 * kShapeStrain);
  md +=
      "| substeps | stable | keeps its shape | stable, with guard | keeps its shape, with guard |\n"
      "|---|---|---|---|---|\n";
  for (int s : report.steps) {
    // With the guard, a case's guarded run where the guard ran it, else its plain run.
    auto pick = [&](bool guard) {
      return [&report, s, guard](const StabilityCase& c) -> const StabilityResult* {
        if (!c.sweeps_ks) return nullptr;
        const StabilityResult* g = guard ? findResult(report, c.name, s, true) : nullptr;
        return g ? g : findResult(report, c.name, s, false);
      };
    };
    md += fmt::format("| {} | {} | {} | {} | {} |\n", s, largestKs(cases, pick(false), isStable),
                      largestKs(cases, pick(false), keepsShape), largestKs(cases, pick(true), isStable),
                      largestKs(cases, pick(true), keepsShape));
  }
  for (Integrator integrator : report.implicit)
    md += implicitMarkdown(report, cases, integrator);
  return md;
}

}  // namespace drape
