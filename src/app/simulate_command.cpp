// `drape simulate`: run a scene headless and print a summary; --out writes the final positions.
#include "app/commands.hpp"
#include "app/export.hpp"
#include "app/measure.hpp"
#include "app/options.hpp"
#include "app/output.hpp"
#include "app/progress.hpp"
#include "app/solver_factory.hpp"
#include "core/metrics.hpp"
#include "core/stability.hpp"
#include "cpu/collision_pairs.hpp"

#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>

namespace drape {

namespace {

struct SimulateOptions {
  std::string scene;
  int frames = 90;
  std::string solver = "cpu";
  std::string out;
  bool verbose = false;
  bool auto_substeps = false;
  int threads = 0;
  std::string team = "auto";
  std::string export_path;
  std::string export_format;
  int every = 1;
  std::string integrator;  // empty: the scene's
  bool collide_held_pairs = false;
  bool waits = false;
};

void printSummary(const Scene& scene, Solver& solver, int frames, double wall_ms) {
  const Positions x = solver.readPositions();
  const glm::dvec3 c = centroid(x);
  fmt::print("scene        {}\n", scene.path);
  fmt::print("solver       {}\n", solver.name());
  fmt::print("frames       {} ({} substeps of {:.6g} s)\n", frames, solver.substeps(), scene.sim.dt());
  fmt::print("simulated    {:.4f} s\n", solver.time());
  fmt::print("y range      [{:.5f}, {:.5f}] m\n", minY(x), maxY(x));
  fmt::print("centroid     ({:.5f}, {:.5f}, {:.5f}) m\n", c.x, c.y, c.z);
  fmt::print("max strain   {:.4f}\n", maxStrain(solver.topology(), scene.cloth, x));
  const std::vector<double> d = colliderDistances(scene, x);
  const std::size_t planes_end = scene.spheres.size() + scene.planes.size();
  for (std::size_t i = 0; i < d.size(); ++i) {
    const std::string name = i < scene.spheres.size() ? fmt::format("sphere {}", i)
                             : i < planes_end         ? fmt::format("plane {}", i - scene.spheres.size())
                                                      : fmt::format("mesh {}", i - planes_end);
    fmt::print("{:<12} {:.5f} m (closest point; negative is inside)\n", name, d[i]);
  }
  // Timing is the one line that differs between runs; everything above is deterministic.
  fmt::print("time         {:.3f} ms per frame\n", frames > 0 ? wall_ms / frames : 0.0);
}

// Warns when the scene is beyond the explicit-integration bound; with --auto-substeps raises its substeps
// to the smallest count inside it instead (same damping and friction per second).
Scene guardStability(Scene scene, bool auto_substeps) {
  const StabilityCheck bound = checkStability(scene);
  if (bound.ok) return scene;
  if (!auto_substeps) {
    fmt::print(stderr, "drape: warning: {}: {}\n", scene.path, bound.message);
    return scene;
  }
  Scene raised = withStableSubsteps(scene);
  if (!checkStability(raised).ok) throw CommandError(kExitBadInput, fmt::format("{}: {}", scene.path, bound.message));
  fmt::print(stderr, "drape: {}: --auto-substeps: {} substeps per frame instead of {}\n", scene.path,
             raised.sim.steps_per_frame, scene.sim.steps_per_frame);
  return raised;
}

// A cloth finer than its thickness: pairs of points closer than 2 x thickness at rest are held by the springs,
// and self-collision skips them (physics::heldAtRest). Where there are any, the result differs from a solver
// that collides them (CS184's): say so.
void warnAboutHeldPairs(const Scene& scene, const Topology& topology) {
  if (!scene.sim.self_collision) return;
  const double range = 2.0 * scene.cloth.thickness;
  const HeldPairs held = heldPairsAtRest(topology.initial_positions, range);
  if (held.count == 0) return;
  fmt::print(stderr,
             "drape: warning: {}: cloth.thickness: 2 x thickness ({:.3g} mm) is more than the rest distance of {} "
             "point pairs (the closest {:.3g} mm apart): self-collision skips them as pairs the springs hold\n",
             scene.path, range * 1e3, held.count, held.closest * 1e3);
}

void runSimulate(const SimulateOptions& o) {
  if (!o.out.empty()) checkOutputFile(o.out);  // before the run, not after it
  const ExportTarget export_target =
      o.export_path.empty() ? ExportTarget{} : resolveExport(o.export_path, o.export_format);
  Scene loaded = loadScene(o.scene);
  applyIntegrator(loaded, o.integrator);
  const Scene scene = guardStability(std::move(loaded), o.auto_substeps);
  SolverFactory factory({.verbose = o.verbose});  // before the solver: it owns the solver's GL context
  auto solver = factory.make(scene, o.solver,
                             {.threads = o.threads,
                              .collide_held_pairs = o.collide_held_pairs,
                              .team_always = o.team == "always",
                              .record_waits = o.waits});
  if (!o.collide_held_pairs) warnAboutHeldPairs(scene, solver->topology());
  std::optional<ClothExport> exporter;
  if (!o.export_path.empty()) exporter.emplace(export_target, scene, solver->topology(), o.frames / o.every * o.every);
  if (o.verbose) fmt::print(stderr, "{}", describePasses(*solver));
  const auto start = std::chrono::steady_clock::now();
  if (exporter) exporter->add(0, solver->readPositions());
  const auto stopIfBlownUp = [&](const Health& h) {
    if (h.ok()) return;
    const long long frame = (h.substeps + scene.sim.steps_per_frame - 1) / scene.sim.steps_per_frame;
    throw CommandError(kExitBlowUp, fmt::format("{}: blew up at frame {}: {}{}", scene.path, frame, h.describe(),
                                                exporter ? keepExport(*exporter) : ""));
  };
  TerminalProgress progress("simulate: frame", o.frames, ::isatty(STDERR_FILENO));
  for (int f = 0; f < o.frames; ++f) {
    solver->stepFrame();
    progress.update(f + 1);
    // A frame to be written is checked first: its read-back waits for the GPU anyway, and garbage is
    // never written. Every other frame is checked a frame late (recentHealth), which makes the CPU wait
    // for nothing: a garbage run still stops within a frame of it.
    const bool exported = exporter && (f + 1) % o.every == 0;
    stopIfBlownUp(exported ? solver->health() : solver->recentHealth());
    if (exported) exporter->add(f + 1, solver->readPositions());
  }
  stopIfBlownUp(solver->health());              // the last frame, which recentHealth may not have seen
  const Positions x = solver->readPositions();  // also waits for the GPU before the clock stops
  progress.finish();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!allFinite(x))
    throw CommandError(kExitBlowUp,
                       fmt::format("{}: the simulation became non-finite within {} frames", scene.path, o.frames));
  // The files first: the summary measures the cloth (distances to the obstacles) and goes to a stream that
  // may fail; neither may cost the run's output.
  if (!o.out.empty()) writePositionsJson(o.out, x);
  if (exporter) exporter->finish();
  printSummary(scene, *solver, o.frames, ms);
  if (o.waits) fmt::print("{}", describeWaits(*solver));
  if (o.verbose) fmt::print(stderr, "{}{}", describeSelfCollision(*solver), describeThreads(*solver));
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw CommandError(kExitFailure,
                       fmt::format("simulate: cannot write the summary to standard output: {}", std::strerror(errno)));
}

}  // namespace

void addSimulateCommand(CLI::App& app) {
  auto opts = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Run a scene headless and print a summary");
  cmd->add_option("scene", opts->scene, "Scene JSON file")->required();
  cmd->add_option("--frames", opts->frames, "Frames to simulate")->check(kNonNegative);
  cmd->add_option(
         "--solver", opts->solver,
         "cpu (float), cpu64 (double), gpu (the path chosen for the device), gpu-general, gpu-tiled or gpu-onedispatch")
      ->check(CLI::IsMember(solverNames(false)))
      ->capture_default_str();
  addIntegratorOption(cmd, opts->integrator);
  cmd->add_option("--out", opts->out, "Write the final positions as JSON [[x,y,z],...]");
  cmd->add_flag("--verbose,-v", opts->verbose, "List the passes and dispatches per frame");
  cmd->add_option("--threads", opts->threads,
                  "CPU solvers' threads (0: every core); every count computes the same bytes")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--team", opts->team,
                  "CPU solvers with several threads: auto (the solver times a team against one thread as it runs, "
                  "below 32768 points) or always (every substep on the team, to measure it)")
      ->check(CLI::IsMember({"auto", "always"}))
      ->capture_default_str();
  cmd->add_flag("--waits", opts->waits,
                "CPU solvers on a team: where its threads waited for each other, by the line of the code that waits, "
                "and for how long (each wait timed: the run takes a little longer)");
  cmd->add_option("--export", opts->export_path,
                  "Write the cloth per exported frame: PATH_NNNN.obj or .ply, or one PATH.usda; a folder (DIR/) gets "
                  "cloth_NNNN.obj inside; missing folders are made");
  cmd->add_option("--format", opts->export_format,
                  "--export format: obj, ply or usda, which decides the files' extension (default: PATH's extension; "
                  "obj for a folder)")
      ->check(CLI::IsMember({"obj", "ply", "usda"}));
  cmd->add_option("--every", opts->every, "--export every K-th frame (frame 0 is the initial state)")
      ->check(CLI::Range(1, 1000000));
  cmd->add_flag("--auto-substeps", opts->auto_substeps,
                "Raise the substeps per frame to stay inside the explicit-integration bound");
  cmd->add_flag("--collide-held-pairs", opts->collide_held_pairs,
                "Self-collision also between the points closer than 2 x thickness at rest, which it skips as held by "
                "the springs: CS184's rule, to measure what skipping changes (cpu, cpu64)");
  cmd->callback([opts] { runSimulate(*opts); });
}

}  // namespace drape
