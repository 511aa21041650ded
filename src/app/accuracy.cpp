#include "app/accuracy.hpp"
#include "app/jobs.hpp"
#include "app/progress.hpp"

#include "app/command_error.hpp"

#include "core/metrics.hpp"
#include "core/stability.hpp"
#include "cpu/cpu_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>

namespace drape {

namespace {

using Clock = std::chrono::steady_clock;

// A run to the last sample frame: positions at each sample frame, stopped at the first blow-up.
struct Trajectory {
  std::vector<Positions> at;  // one per sample frame reached
  std::string unstable;
  int unstable_frame = -1;
  double step_ms = 0;  // wall time of stepping only (plus the GPU's end-of-frame wait)
  int frames_run = 0;
};

Trajectory runTrajectory(Solver& solver, const std::vector<int>& sample_frames) {
  Trajectory out;
  const Topology& topo = solver.topology();
  const Positions& start = topo.initial_positions;
  std::size_t next = 0;
  for (int f = 1; f <= sample_frames.back(); ++f) {
    const auto t0 = Clock::now();
    solver.stepFrame();
    solver.finish();
    out.step_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    out.frames_run = f;
    Positions x = solver.readPositions();
    const std::string why = detectBlowUp(topo, solver.scene().cloth, start, x);
    if (!why.empty()) {
      out.unstable = why;
      out.unstable_frame = f;
      break;
    }
    if (f == sample_frames[next]) {
      out.at.push_back(std::move(x));
      ++next;
    }
  }
  return out;
}

double penetration(const Scene& scene, const Positions& x) {
  double deepest = 0;
  for (double d : colliderDistances(scene, x))
    deepest = std::max(deepest, -d);
  return deepest;
}

ErrorSample compare(const Scene& scene, const Topology& topo, int frame, const Positions& x, const Positions& ref) {
  ErrorSample s;
  s.frame = frame;
  s.t = frame / scene.sim.frames_per_sec;
  s.rms_error = rmsDeviation(x, ref) / clothSize(scene.cloth);
  s.max_error = maxDeviation(x, ref);
  s.max_strain = maxStrain(topo, scene.cloth, x);
  s.penetration = penetration(scene, x);
  return s;
}

// An XPBD or VBD run is named by its solver and the integrator ("cpu+xpbd", "gpu+vbd"), so that every
// integrator's runs share the table, the CSV and the plot, each its own column and curve.
Integrator runIntegrator(const std::string& run_solver) {
  const std::size_t plus = run_solver.rfind('+');
  if (plus != std::string::npos)
    for (Integrator i : kIntegrators)
      if (run_solver.compare(plus + 1, std::string::npos, integratorName(i)) == 0) return i;
  return Integrator::Verlet;
}

std::string baseSolver(const std::string& run_solver) {
  return runIntegrator(run_solver) == Integrator::Verlet ? run_solver : run_solver.substr(0, run_solver.rfind('+'));
}

std::string integratorSuffix(Integrator i) {
  return i == Integrator::Verlet ? "" : std::string("+") + integratorName(i);
}

// Every configuration simulates the same material: damping is rescaled to the scene's loss per second.
// The references are Verlet's whatever the scene says: the converged solution of the spring model, which
// both integrators approach as their substeps grow.
Scene configure(const Scene& scene, int steps, int passes, Integrator integrator = Integrator::Verlet) {
  Scene s = withSubsteps(scene, steps);
  s.sim.stretch_passes = passes;
  s.sim.integrator = integrator;
  return s;
}

std::string fixed(double v, const char* spec = "{:.4g}") {
  return fmt::format(fmt::runtime(spec), v);
}

// Precision alone: each float run against the double run with the same substeps and passes, which has
// the same discretisation error. states[i] is runs[i]'s positions at the sample frames.
void compareWithDouble(std::vector<AccuracyRun>& runs, const std::vector<const std::vector<Positions>*>& states,
                       double size) {
  for (std::size_t a = 0; a < runs.size(); ++a) {
    AccuracyRun& run = runs[a];
    for (std::size_t b = 0; b < runs.size(); ++b) {
      const AccuracyRun& twin = runs[b];
      if (twin.solver != "cpu64" + integratorSuffix(runIntegrator(run.solver)) ||
          twin.steps_per_frame != run.steps_per_frame || twin.stretch_passes != run.stretch_passes)
        continue;
      for (std::size_t i = 0; i < run.samples.size() && i < states[a]->size() && i < states[b]->size(); ++i)
        run.samples[i].vs_double = rmsDeviation((*states[a])[i], (*states[b])[i]) / size;
    }
  }
}

}  // namespace

AccuracyReport runAccuracy(const AccuracyOptions& o, const std::function<void(const std::string&)>& progress,
                           const std::function<void(const AccuracyReport&)>& finished) {
  AccuracyReport report;
  report.scene = o.scene;
  report.started_at = utcTimestamp();
  report.machine = readMachineInfo();
  report.options = o;
  const auto start = Clock::now();
  const Scene scene = loadScene(o.scene);
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };

  std::vector<int> frames;
  for (double t : o.times) {
    // In double before any int: t x frames_per_sec can be far beyond int (--times 1e9 wrapped around).
    const double frame = std::round(t * scene.sim.frames_per_sec);
    if (!(frame <= kMaxSampleFrames))
      throw CommandError(kExitBadInput, fmt::format("--times: t = {:g} s is {:g} frames at {:g} frames/s, more than {}",
                                                    t, frame, scene.sim.frames_per_sec, kMaxSampleFrames));
    frames.push_back(std::max(1, int(frame)));
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());

  // The references and their checks are the longest runs and are not timed for the plot, so they run
  // side by side, one per core.
  struct ReferenceJob {
    int passes = 0, steps = 0;
    std::unique_ptr<Solver> solver;
    Trajectory trajectory;
    double wall_s = 0;
  };
  std::vector<ReferenceJob> jobs;
  for (int passes : o.stretch_passes)
    for (int factor : {o.reference_factor, 2 * o.reference_factor})
      jobs.push_back({passes, factor * scene.sim.steps_per_frame, nullptr, {}, 0.0});
  const int reference_jobs = jobsFor(o.jobs, jobs.size());
  say(fmt::format("{} reference runs (cpu64, x{} and x{} substeps), {} at a time", jobs.size(), o.reference_factor,
                  2 * o.reference_factor, reference_jobs));
  forEachJob(jobs.size(), reference_jobs, [&](std::size_t j) {
    const auto t0 = Clock::now();
    jobs[j].solver = std::make_unique<CpuSolver<double>>(configure(scene, jobs[j].steps, jobs[j].passes),
                                                         CpuSolverOptions{.threads = threadsPerJob(reference_jobs)});
    jobs[j].trajectory = runTrajectory(*jobs[j].solver, frames);
    jobs[j].wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  });

  SolverFactory factory({.skip_unavailable = true});
  std::map<int, std::vector<Positions>> references;
  for (std::size_t j = 0; j < jobs.size(); j += 2) {
    const ReferenceJob& ref = jobs[j];
    const ReferenceJob& chk = jobs[j + 1];
    ReferenceCheck check;
    check.stretch_passes = ref.passes;
    check.steps_per_frame = ref.steps;
    check.check_steps_per_frame = chk.steps;
    check.wall_s = ref.wall_s + chk.wall_s;
    if (!ref.trajectory.unstable.empty())
      check.unstable = fmt::format("reference, frame {}: {}", ref.trajectory.unstable_frame, ref.trajectory.unstable);
    else if (!chk.trajectory.unstable.empty())
      check.unstable = fmt::format("check, frame {}: {}", chk.trajectory.unstable_frame, chk.trajectory.unstable);
    for (std::size_t i = 0; i < std::min(ref.trajectory.at.size(), chk.trajectory.at.size()); ++i)
      check.samples.push_back(
          compare(ref.solver->scene(), ref.solver->topology(), frames[i], ref.trajectory.at[i], chk.trajectory.at[i]));
    references[ref.passes] = ref.trajectory.at;
    say(fmt::format("reference cpu64 x{} substeps, {} stretch passes: {}", o.reference_factor, ref.passes,
                    check.unstable.empty() && !check.samples.empty()
                        ? fmt::format("differs from x{} by {:.3g} (RMS / size) at t = {:.3g} s", 2 * o.reference_factor,
                                      check.samples.back().rms_error, check.samples.back().t)
                        : "unstable: " + check.unstable));
    report.references.push_back(std::move(check));
  }

  // The timed runs: CPU runs side by side, each on its share of the cores (their times are then those
  // of that many threads, which the report states); GPU runs one at a time afterwards, on the one
  // context the factory holds.
  struct SweepJob {
    AccuracyRun run;
    std::vector<Positions> states;  // positions at the sample frames
    bool done = false;
  };
  std::vector<SweepJob> sweep;
  for (int passes : o.stretch_passes)
    for (const std::string& name : o.solvers)
      for (int steps : o.steps) {
        SweepJob job;
        job.run.solver = name;
        job.run.steps_per_frame = steps;
        job.run.stretch_passes = passes;
        sweep.push_back(std::move(job));
      }
  std::vector<std::size_t> cpu_jobs, gpu_jobs;
  for (std::size_t j = 0; j < sweep.size(); ++j)
    (isGpuSolver(baseSolver(sweep[j].run.solver)) ? gpu_jobs : cpu_jobs).push_back(j);
  report.jobs = jobsFor(o.jobs, cpu_jobs.size());
  report.threads_per_run = threadsPerJob(report.jobs);
  std::mutex say_mutex;
  // The time left weighs each run by its substeps (VBD's twice: it costs about twice Verlet's on the CPU), and
  // the GPU runs, which come last, by what they cost here: until one has finished, a GPU substep is taken as
  // 3 times a one-thread CPU run's (llvmpipe, docs/results/README.md), alone where the CPU runs went `jobs`
  // at a time. A GPU that is faster brings the estimate down once its first run is in.
  std::vector<double> cost;
  std::vector<int> lane;
  for (const SweepJob& job : sweep) {
    cost.push_back(job.run.steps_per_frame * (runIntegrator(job.run.solver) == Integrator::Vbd ? 2.0 : 1.0));
    lane.push_back(isGpuSolver(baseSolver(job.run.solver)) ? 1 : 0);
  }
  SweepEstimate estimate(cost, lane, 3.0 * report.jobs);
  // The report with the runs finished so far, in sweep order; called with say_mutex held.
  auto reportDone = [&] {
    if (!finished) return;
    AccuracyReport partial = report;
    std::vector<const std::vector<Positions>*> states;
    for (const SweepJob& job : sweep)
      if (job.done) {
        partial.runs.push_back(job.run);
        states.push_back(&job.states);
      }
    compareWithDouble(partial.runs, states, clothSize(scene.cloth));
    partial.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    finished(partial);
  };
  reportDone();  // the references
  auto runOne = [&](std::size_t index, SolverFactory& maker) {
    SweepJob& job = sweep[index];
    AccuracyRun& run = job.run;
    const Scene s = configure(scene, run.steps_per_frame, run.stretch_passes, runIntegrator(run.solver));
    std::unique_ptr<Solver> solver;
    try {
      solver = maker.make(s, baseSolver(run.solver), {.threads = report.threads_per_run});
    } catch (const SkippedRun& e) {
      run.skipped = e.what();
    }
    if (solver) {
      Trajectory traj = runTrajectory(*solver, frames);
      run.unstable = traj.unstable;
      run.unstable_frame = traj.unstable_frame;
      run.ms_per_sim_s = traj.step_ms / (traj.frames_run / s.sim.frames_per_sec);
      const std::vector<Positions>& ref = references.at(run.stretch_passes);
      for (std::size_t i = 0; i < std::min(traj.at.size(), ref.size()); ++i)
        run.samples.push_back(compare(s, solver->topology(), frames[i], traj.at[i], ref[i]));
      job.states = std::move(traj.at);
    }
    std::lock_guard<std::mutex> lock(say_mutex);
    job.done = true;
    std::string line = fmt::format("{}: {} {} substeps, {} stretch passes: ", estimate.finished(index), run.solver,
                                   run.steps_per_frame, run.stretch_passes);
    if (!run.skipped.empty())
      line += "skipped (" + run.skipped + ")";
    else if (!run.unstable.empty())
      line += fmt::format("unstable at frame {} ({})", run.unstable_frame, run.unstable);
    else if (!run.samples.empty())
      line += fmt::format("error {:.3g} (RMS / size) at t = {:.3g} s, {:.0f} ms per simulated s",
                          run.samples.back().rms_error, run.samples.back().t, run.ms_per_sim_s);
    say(line);
    reportDone();
  };
  say(fmt::format("{} CPU runs, {} at a time ({} solver thread{} each), then {} GPU runs", cpu_jobs.size(), report.jobs,
                  report.threads_per_run, report.threads_per_run == 1 ? "" : "s", gpu_jobs.size()));
  forEachJob(cpu_jobs.size(), report.jobs, [&](std::size_t k) {
    SolverFactory cpu_factory({.skip_unavailable = true});  // CPU solvers only: no context off the main thread
    runOne(cpu_jobs[k], cpu_factory);
  });
  for (std::size_t j : gpu_jobs)
    runOne(j, factory);
  std::vector<const std::vector<Positions>*> states;  // per run, its positions at the sample frames
  for (SweepJob& job : sweep) {
    report.runs.push_back(std::move(job.run));
    states.push_back(&job.states);
  }
  compareWithDouble(report.runs, states, clothSize(scene.cloth));
  if (const GlInfo* gl = factory.glInfo()) report.gl = *gl;
  report.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

std::string accuracyCsv(const AccuracyReport& r) {
  std::string csv =
      "solver,steps_per_frame,stretch_passes,t,frame,status,unstable_frame,rms_error_over_size,max_error_m,max_strain,"
      "penetration_m,ms_per_sim_s,vs_cpu64_rms_over_size,note\n";
  for (const AccuracyRun& run : r.runs) {
    const std::string head = fmt::format("{},{},{}", run.solver, run.steps_per_frame, run.stretch_passes);
    for (const ErrorSample& s : run.samples)
      csv += fmt::format("{},{:.6g},{},ok,,{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{},\n", head, s.t, s.frame, s.rms_error,
                         s.max_error, s.max_strain, s.penetration, run.ms_per_sim_s,
                         s.vs_double >= 0 ? fmt::format("{:.9g}", s.vs_double) : "");
    if (!run.skipped.empty()) {
      csv += fmt::format("{},,,skipped,,,,,,,,\"{}\"\n", head, run.skipped);
    } else if (!run.unstable.empty()) {
      csv += fmt::format("{},,,unstable,{},,,,,{:.6g},,\"{}\"\n", head, run.unstable_frame, run.ms_per_sim_s,
                         run.unstable);
    }
  }
  return csv;
}

std::string referenceCsv(const AccuracyReport& r) {
  std::string csv =
      "stretch_passes,steps_per_frame,check_steps_per_frame,t,frame,status,rms_difference_over_size,"
      "max_difference_m,reference_max_strain,reference_penetration_m,wall_s,note\n";
  for (const ReferenceCheck& c : r.references) {
    const std::string head = fmt::format("{},{},{}", c.stretch_passes, c.steps_per_frame, c.check_steps_per_frame);
    for (const ErrorSample& s : c.samples)
      csv += fmt::format("{},{:.6g},{},ok,{:.9g},{:.9g},{:.9g},{:.9g},{:.3f},\n", head, s.t, s.frame, s.rms_error,
                         s.max_error, s.max_strain, s.penetration, c.wall_s);
    if (!c.unstable.empty()) csv += fmt::format("{},,,unstable,,,,,{:.3f},\"{}\"\n", head, c.wall_s, c.unstable);
  }
  return csv;
}

namespace {

const AccuracyRun* findRun(const AccuracyReport& r, const std::string& solver, int steps, int passes) {
  for (const AccuracyRun& run : r.runs)
    if (run.solver == solver && run.steps_per_frame == steps && run.stretch_passes == passes) return &run;
  return nullptr;
}

// One table cell: the largest value of the chosen figure over the sample times (an error can peak
// mid-run and shrink as the cloth settles), or why there is none.
std::string cell(const AccuracyRun* run, double (*figure)(const AccuracyRun&, const ErrorSample&)) {
  if (!run) return "–";
  if (!run->skipped.empty()) return "skipped";
  if (!run->unstable.empty()) return fmt::format("unstable (frame {})", run->unstable_frame);
  if (run->samples.empty()) return "–";
  double worst = -1;
  for (const ErrorSample& s : run->samples)
    worst = std::max(worst, figure(*run, s));
  return worst < 0 ? "–" : fixed(worst, "{:.3g}");
}

std::string solverLabel(const AccuracyReport& r, const std::string& solver) {
  if (const Integrator i = runIntegrator(solver); i != Integrator::Verlet)
    return solverLabel(r, baseSolver(solver)) + ", " + integratorName(i);
  if (isGpuSolver(solver) && r.gl && r.gl->software) return solver + " (llvmpipe)";
  if (solver == "cpu") return "cpu (float, displacement)";
  if (solver == "cpu-xprev") return "cpu-xprev (float, x_prev)";
  if (solver == "cpu64") return "cpu64 (double)";
  return solver;
}

}  // namespace

ConvergenceOrder convergenceOrder(const AccuracyReport& report, const std::string& solver, int stretch_passes) {
  double resolution = 0;
  for (const ReferenceCheck& c : report.references)
    if (c.stretch_passes == stretch_passes)
      for (const ErrorSample& s : c.samples)
        resolution = std::max(resolution, s.rms_error);
  ConvergenceOrder out;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int steps : report.options.steps) {
    const AccuracyRun* run = findRun(report, solver, steps, stretch_passes);
    if (!run || !run->skipped.empty() || !run->unstable.empty() || run->samples.empty()) continue;
    double error = 0;
    for (const ErrorSample& s : run->samples)
      error = std::max(error, s.rms_error);
    if (!(error >= kResolvedFactor * resolution) || !(error > 0)) continue;
    const double x = std::log(double(steps)), y = std::log(error);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    if (out.runs == 0) out.smallest_steps = steps;
    out.largest_steps = steps;
    ++out.runs;
  }
  const double n = out.runs;
  out.order = out.runs >= 3 ? -(n * sxy - sx * sy) / (n * sxx - sx * sx) : std::nan("");
  return out;
}

std::string accuracyMarkdown(const AccuracyReport& r) {
  const AccuracyOptions& o = r.options;
  std::string md =
      fmt::format("Accuracy of `{}` on {} ({} logical cores, load average {} at the start){}; {:.0f} s in all.\n\n",
                  r.scene, r.machine.cpu_model, r.machine.logical_cores, r.machine.load_average,
                  r.gl ? fmt::format(", GPU solver on {}{}", r.gl->renderer,
                                     r.gl->software ? " (software rasteriser: its times are not GPU times)" : "")
                       : "",
                  r.wall_s);
  md += fmt::format(
      "CPU runs ran {} at a time with {} solver thread{} each, so their times are {}-thread times; GPU runs ran one "
      "at a time.\n\n",
      r.jobs, r.threads_per_run, r.threads_per_run == 1 ? "" : "s", r.threads_per_run);
  md += fmt::format(
      "Reference: CPU double with {}x the scene's substeps, per stretch-pass count; checked against {}x. Damping and "
      "collision friction are fractions per substep in the model, so every configuration has them rescaled to the "
      "scene's loss per simulated second (1 - d_s = (1 - d)^(S/s)); without that, more substeps would mean a more "
      "damped cloth, not a more accurate one.\n\n",
      o.reference_factor, 2 * o.reference_factor);
  md +=
      "| stretch passes | reference substeps | t (s) | reference vs check (RMS / size) | max (m) | reference max "
      "strain |\n";
  md += "|---|---|---|---|---|---|\n";
  for (const ReferenceCheck& c : r.references) {
    for (const ErrorSample& s : c.samples)
      md += fmt::format("| {} | {} | {:.3g} | {:.3g} | {:.3g} | {:.3g} |\n", c.stretch_passes, c.steps_per_frame, s.t,
                        s.rms_error, s.max_error, s.max_strain);
    if (!c.unstable.empty())
      md += fmt::format("| {} | {} | – | unstable: {} | | |\n", c.stretch_passes, c.steps_per_frame, c.unstable);
  }
  std::string times;
  for (double t : o.times)
    times += fmt::format("{}{:g}", times.empty() ? "" : ", ", t);
  struct Figure {
    std::string title;
    double (*value)(const AccuracyRun&, const ErrorSample&);
  };
  const std::string over = ", largest over t = " + times + " s";
  std::vector<Figure> figures = {
      {"RMS position error / cloth size" + over, [](const AccuracyRun&, const ErrorSample& s) { return s.rms_error; }},
      {"Float round-off alone: RMS distance / cloth size to cpu64 with the same substeps and passes" + over,
       [](const AccuracyRun&, const ErrorSample& s) { return s.vs_double; }},
      {"Max strain" + over, [](const AccuracyRun&, const ErrorSample& s) { return s.max_strain; }},
      {"Wall ms per simulated second (stepping only)",
       [](const AccuracyRun& run, const ErrorSample&) { return run.ms_per_sim_s; }},
  };
  // Only where something went inside a collider: a column of zeros says nothing about a scene without one.
  const bool penetrates = std::any_of(r.runs.begin(), r.runs.end(), [](const AccuracyRun& run) {
    return std::any_of(run.samples.begin(), run.samples.end(), [](const ErrorSample& s) { return s.penetration > 0; });
  });
  if (penetrates)
    figures.insert(figures.begin() + 3,
                   Figure{"Deepest penetration into a collider, mm" + over,
                          [](const AccuracyRun&, const ErrorSample& s) { return 1000.0 * s.penetration; }});
  for (const Figure& fig : figures)
    for (int passes : o.stretch_passes) {
      md += fmt::format("\n{}, {} stretch pass{}:\n\n| substeps |", fig.title, passes, passes == 1 ? "" : "es");
      for (const std::string& solver : o.solvers)
        md += fmt::format(" {} |", solverLabel(r, solver));
      md += "\n|---|";
      for (std::size_t i = 0; i < o.solvers.size(); ++i)
        md += "---|";
      md += "\n";
      for (int steps : o.steps) {
        md += fmt::format("| {} |", steps);
        for (const std::string& solver : o.solvers)
          md += fmt::format(" {} |", cell(findRun(r, solver, steps, passes), fig.value));
        md += "\n";
      }
    }
  md += fmt::format(
      "\nOrder of convergence: the slope of log(RMS error) against log(substeps), fitted over the stable runs whose "
      "error is at least {:g} times the reference's own (the runs used in brackets). It measures the integrator only "
      "with the stretch limit off (0 passes): with it on, the limit's corrections set much of the error.\n\n| "
      "stretch passes |",
      kResolvedFactor);
  for (const std::string& solver : o.solvers)
    md += " " + solverLabel(r, solver) + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < o.solvers.size(); ++i)
    md += "---|";
  md += "\n";
  for (int passes : o.stretch_passes) {
    md += fmt::format("| {} |", passes);
    for (const std::string& solver : o.solvers) {
      const ConvergenceOrder c = convergenceOrder(r, solver, passes);
      md += c.runs >= 3 ? fmt::format(" {:.2f} ({} runs, {}–{}) |", c.order, c.runs, c.smallest_steps, c.largest_steps)
                        : fmt::format(" – ({} run{}) |", c.runs, c.runs == 1 ? "" : "s");
    }
    md += "\n";
  }
  return md;
}

}  // namespace drape
