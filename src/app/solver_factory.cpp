#include "app/solver_factory.hpp"

#include "app/command_error.hpp"
#include "core/memory_stage.hpp"
#include "cpu/cpu_solver.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "gpu/gpu_solver.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>

namespace drape {

const std::vector<SolverKind>& solverKinds() {
  static const std::vector<SolverKind> kinds = {
      {"cpu", "CPU reference in float, the GPU's arithmetic", false},
      {"cpu64", "CPU reference in double", false},
      {"gpu", "OpenGL 4.5 compute shaders, the path chosen for the device", false},
      {"gpu-general", "the GPU's general path: a dispatch per pass and substep", false},
      {"gpu-tiled", "the general path with the stretch limit in one dispatch of blocks (grid cloths)", false},
      {"gpu-onedispatch", "the GPU's one-dispatch path: a frame in one work group (small cloths)", false},
      {"cpu-xprev", "CPU float with CS184's x_prev form of Verlet (its round-off, measured)", true},
  };
  return kinds;
}

bool isGpuSolver(const std::string& name) {
  return name == "gpu" || name == "gpu-general" || name == "gpu-tiled" || name == "gpu-onedispatch";
}

std::vector<std::string> solverNames(bool with_measurement_only) {
  std::vector<std::string> names;
  for (const SolverKind& kind : solverKinds())
    if (with_measurement_only || !kind.measurement_only) names.push_back(kind.name);
  return names;
}

SolverFactory::SolverFactory(SolverFactoryOptions options) : options_(options) {}

SolverFactory::~SolverFactory() = default;

std::unique_ptr<Solver> SolverFactory::make(const Scene& scene, const std::string& name, SolverRequest request) {
  const MemoryStage stage(fmt::format("building the {} solver for {} points", name, scene.cloth.pointCount()));
  CpuSolverOptions cpu{.threads = request.threads,
                       .skip_held_pairs = !request.collide_held_pairs,
                       .pass_timing = request.pass_timing,
                       .record_waits = request.record_waits};
  if (request.team_always) cpu.team_min_points = 0;
  if (name == "cpu") return std::make_unique<CpuSolver<float>>(scene, cpu);
  if (name == "cpu64") return std::make_unique<CpuSolver<double>>(scene, cpu);
  if (name == "cpu-xprev")
    return std::make_unique<CpuSolver<float>>(scene, CpuSolverOptions{.form = VerletForm::PreviousPosition,
                                                                      .threads = request.threads,
                                                                      .skip_held_pairs = !request.collide_held_pairs,
                                                                      .team_min_points = cpu.team_min_points,
                                                                      .pass_timing = cpu.pass_timing,
                                                                      .record_waits = cpu.record_waits});
  if (isGpuSolver(name)) {
    if (request.collide_held_pairs)
      throw CommandError(kExitBadInput, "--collide-held-pairs: the CPU solvers only (cpu, cpu64)");
    if (request.record_waits) throw CommandError(kExitBadInput, "--waits: the CPU solvers only (cpu, cpu64)");
    if (request.team_always) throw CommandError(kExitBadInput, "--team always: the CPU solvers only (cpu, cpu64)");
    return makeGpu(scene, name, request);
  }
  throw CommandError(kExitBadInput,
                     fmt::format("--solver: unknown solver '{}' ({})", name, fmt::join(solverNames(true), ", ")));
}

void SolverFactory::unavailable(int status, const std::string& why) {
  if (options_.skip_unavailable) throw SkippedRun(why);
  throw CommandError(status, why);
}

std::unique_ptr<Solver> SolverFactory::makeGpu(const Scene& scene, const std::string& name,
                                               const SolverRequest& request) {
  if (!options_.use_current_context) {
    if (!no_context_.empty()) unavailable(kExitNoGl, no_context_);
    if (!context_) {
      try {
        context_ = std::make_unique<gl::HeadlessContext>(gl::HeadlessContext::create());
      } catch (const gl::ContextError& e) {
        no_context_ = fmt::format("gpu solver: no OpenGL 4.5 context: {}", e.what());
        unavailable(kExitNoGl, no_context_);
      }
      if (options_.verbose)
        fmt::print(stderr, "gpu solver: GL_RENDERER {} | GL_VERSION {} ({})\n", context_->info().renderer,
                   context_->info().version, context_->info().platform);
    }
    context_->makeCurrent();
  }
  GpuSolverOptions options;
  options.timing = request.pass_timing;
  options.path = name == "gpu-general"       ? GpuPath::General
                 : name == "gpu-tiled"       ? GpuPath::Tiled
                 : name == "gpu-onedispatch" ? GpuPath::OneDispatch
                                             : GpuPath::Auto;
  std::unique_ptr<GpuSolver> solver;
  try {
    solver = std::make_unique<GpuSolver>(scene, options);
  } catch (const GpuLimitError& e) {
    unavailable(kExitBadInput, fmt::format("{}: {}", scene.path, e.what()));
  }
  if (gl_info_.renderer.empty()) {
    const gl::ContextInfo& info = context_ ? context_->info() : solver->contextInfo();
    gl_info_ = {info.vendor,   info.renderer, info.version,          info.glsl_version,
                info.platform, info.software, gl::timerQueriesWork()};
  }
  return solver;
}

namespace {

// How the lists' checks kept them: the box of every displacement alone, or a closer look at the tiles
template <class T>
std::string describeChecks(const CollisionPairs<T>& p) {
  std::string kept;
  if (p.checksClearedWhole() > 0)
    kept = fmt::format("{} checks cleared by the box of every displacement alone", p.checksClearedWhole());
  if (p.closerLooksKept() > 0)
    kept += fmt::format("{}kept {} times by a closer look at tiles their boxes did not clear", kept.empty() ? "" : "; ",
                        p.closerLooksKept());
  return kept.empty() ? kept : " (" + kept + ")";
}

template <class T>
std::string describePairs(const CpuSolver<T>& cpu) {
  const CollisionPairs<T>& p = cpu.collisionPairs();
  const double n = double(cpu.positions().size());
  if (!cpu.scene().sim.self_collision || p.rebuilds() == 0 || n == 0) return "";
  return fmt::format(
      "self-collision: lists built {} times in {} substeps{}, {:.2f} entries a point (mean over the builds; {:.2f} "
      "at the last); stencil: {} grid offsets{}; {:.3f} pairs in range a point and substep; skin {} at the end, {} "
      "switches\n",
      p.rebuilds(), cpu.substeps(), describeChecks(p), double(p.entriesBuilt()) / double(p.rebuilds()) / n,
      double(p.pairCount()) / n, p.stencil().size(),
      p.squaresUsed()
          ? fmt::format(", {:.0f}% of its squares' offsets passed over at the last substep", 100 * p.squaresRuledOut())
          : std::string(" tested every substep"),
      double(cpu.pairTerms()) / n / double(cpu.substeps()), cpu.wideSkin() ? "wide" : "narrow", cpu.skinSwitches());
}

template <class T>
std::string describeTeam(const CpuSolver<T>& cpu) {
  if (cpu.teamThreads() <= 1 || cpu.substeps() == 0) return "";
  std::string out =
      fmt::format("threads: a team of {} ran {} of {} substeps", cpu.teamThreads(), cpu.teamSubsteps(), cpu.substeps());
  if (const TeamTrial* trial = cpu.teamTrial()) {
    if (std::isnan(trial->teamOverSolo()))
      out += ", one thread the others (the team was not tried: the machine had no core free for it)";
    else
      out += fmt::format(
          ", one thread the others (timed as it ran: at its last probe the team took {:.2f}x one "
          "thread's time)",
          trial->teamOverSolo());
  }
  // Where the shares moved with the work (balanceShares), each thread's part of them at the end
  const auto parts = [](const std::vector<long long>& bounds) {
    std::string text;
    for (std::size_t t = 0; t + 1 < bounds.size(); ++t)
      text +=
          fmt::format("{}{:.0f}", t > 0 ? "/" : "", 100.0 * double(bounds[t + 1] - bounds[t]) / double(bounds.back()));
    return text + "%";
  };
  std::vector<std::string> shares;
  if (const std::vector<long long> rows = cpu.colourRows(); rows.size() > 2 && rows.back() > 0)
    shares.push_back("the stretch limit's rows " + parts(rows));
  if (cpu.scene().sim.self_collision && cpu.findShares().size() > 2 && cpu.findShares().back() > 0) {
    shares.push_back("self-collision's search " + parts(cpu.findShares()));
    shares.push_back("its sums " + parts(cpu.pairShares()));
  }
  if (!shares.empty()) out += fmt::format("; each thread's share at the end: {}", fmt::join(shares, ", "));
  return out + "\n";
}

// The team's waits by line (WaitLog), the longest first: each thread's count, time and share of the team's time.
template <class T>
std::string describeTeamWaits(const CpuSolver<T>& cpu) {
  const WaitLog* log = cpu.waits();
  if (!log) return "";
  if (cpu.teamSubsteps() == 0 || log->threads() == 0)
    return "waits        none: no substep ran on a team (one thread waits for nothing)\n";
  const double team = cpu.teamSeconds();
  const auto share = [team](double seconds) { return team > 0 ? 100 * seconds / team : 0.0; };
  const std::vector<double> totals = log->totals();
  std::string out = fmt::format("waits        a team of {} ran {} substeps in {:.1f} ms; waiting, thread",
                                log->threads(), cpu.teamSubsteps(), 1e3 * team);
  for (std::size_t t = 0; t < totals.size(); ++t)
    out += fmt::format("{} {} {:.2f} ms ({:.1f}%)", t == 0 ? "" : ", thread", t, 1e3 * totals[t], share(totals[t]));
  out += "\n";
  // By length: the syncs' own latency, uneven shares, a thread that did not run (WaitLog::kLengthBounds)
  const std::vector<WaitLog::Lengths> lengths = log->lengths();
  for (std::size_t t = 0; t < lengths.size(); ++t) {
    const WaitLog::Lengths& l = lengths[t];
    out += fmt::format(
        "  thread {}: {} waits under 1 us took {:.2f} ms, {} of 1-20 us {:.2f} ms, {} of 20 us or more {:.2f} ms\n", t,
        l.count[0], 1e3 * l.seconds[0], l.count[1], 1e3 * l.seconds[1], l.count[2], 1e3 * l.seconds[2]);
  }
  out += "  line that waits                               ";
  for (std::size_t t = 0; t < totals.size(); ++t)
    out += fmt::format("  thread {}: waits, ms, share", t);
  out += "\n";
  for (const WaitLog::Site& s : log->sites()) {
    out += fmt::format("  {:<44}", fmt::format("{}:{}", s.file, s.line));
    for (std::size_t t = 0; t < s.count.size(); ++t)
      out += fmt::format("  {:>9} {:>9.3f} {:>5.1f}%", s.count[t], 1e3 * s.seconds[t], share(s.seconds[t]));
    out += "\n";
  }
  return out;
}

}  // namespace

std::string describeWaits(const Solver& solver) {
  if (const auto* f = dynamic_cast<const CpuSolver<float>*>(&solver)) return describeTeamWaits(*f);
  if (const auto* d = dynamic_cast<const CpuSolver<double>*>(&solver)) return describeTeamWaits(*d);
  return "";
}

std::string describeThreads(const Solver& solver) {
  if (const auto* f = dynamic_cast<const CpuSolver<float>*>(&solver)) return describeTeam(*f);
  if (const auto* d = dynamic_cast<const CpuSolver<double>*>(&solver)) return describeTeam(*d);
  return "";
}

std::string describeSelfCollision(const Solver& solver) {
  if (const auto* f = dynamic_cast<const CpuSolver<float>*>(&solver)) return describePairs(*f);
  if (const auto* d = dynamic_cast<const CpuSolver<double>*>(&solver)) return describePairs(*d);
  return "";
}

std::string describePasses(const Solver& solver) {
  const std::vector<std::string> passes = solver.passes(), frame_passes = solver.framePasses();
  const int substeps = solver.scene().sim.steps_per_frame;
  std::string out;
  if (solver.dispatchesPerSubstep() > 0 && solver.dispatchesPerSubstep() < 1) {
    out = fmt::format("{}: 1 dispatch runs the {} substeps of a frame, {} per frame", solver.name(), substeps,
                      solver.dispatchesPerFrame());
    out += frame_passes.empty() ? "\n" : fmt::format(" (then {} once per frame)\n", frame_passes.size());
    out += "  each substep in that dispatch:\n";
  } else if (solver.dispatchesPerFrame() > 0) {
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
