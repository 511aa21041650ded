// `drape accuracy SCENE`: error against run time for every solver, substep count and stretch-pass
// count; CSV, a markdown summary, and a log-log plot by tools/plot_accuracy.py.
#include "app/accuracy.hpp"
#include "app/commands.hpp"
#include "app/options.hpp"
#include "app/output.hpp"
#include "app/process.hpp"
#include "core/data_dir.hpp"

#include <fmt/core.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace drape {

namespace {

namespace fs = std::filesystem;

struct AccuracyCommandOptions {
  std::string scene;
  std::string out;
  std::vector<int> steps = {5, 10, 20, 30, 60, 120};
  std::vector<std::string> solvers = {"cpu-xprev", "cpu", "cpu64", "gpu"};
  std::vector<int> passes = {1, 2, 4};
  std::vector<double> times = {0.5, 1, 2};
  int reference_factor = 16;
  int jobs = 0;
  bool quick = false;
  bool no_plot = false;
  std::vector<std::string> integrators = {"verlet", "xpbd", "vbd"};
};

// The plot needs Debian's matplotlib, which a pyenv python3 on PATH may not see (docs/design.md section 8).
// DRAPE_PYTHON names another interpreter. No shell: the scene's name and --out reach python as they are.
void plot(const fs::path& dir, const std::string& title) {
  const fs::path script = dataDir("tools") / "plot_accuracy.py";
  const char* python_env = std::getenv("DRAPE_PYTHON");
  const std::string python = python_env && *python_env ? python_env : "/usr/bin/python3";
  if (runProcess({python, "-c", "import matplotlib"}, /*quiet=*/true) != 0) {
    fmt::print(stderr,
               "accuracy: no plot: {} cannot import matplotlib (tools/setup installs python3-matplotlib); the CSV "
               "files are written\n",
               python);
    return;
  }
  // Absolute paths and --title=: a name starting with '-' must not read as an option to argparse.
  const fs::path abs = fs::absolute(dir);
  // matplotlib writes wherever it is told, through links and in place: it draws into a temporary of ours
  // beside accuracy.png (core/atomic_file.hpp), which is renamed over it once it is whole. The name
  // ends in .png: matplotlib picks the format from it.
  checkOutputFile(dir / "accuracy.png");
  TemporaryFile scratch(dir / "accuracy.png", ".png");
  const std::vector<std::string> command = {python,
                                            script.string(),
                                            (abs / "accuracy.csv").string(),
                                            (abs / "reference.csv").string(),
                                            fs::absolute(scratch.path()).string(),
                                            "--title=" + title};
  const int status = runProcess(command);
  struct stat drawn {};
  if (status != 0 || !scratch.stillOurs() || ::fstat(scratch.fd(), &drawn) != 0 || drawn.st_size == 0)
    throw CommandError(kExitFailure, fmt::format("accuracy: {} failed (the CSV files are written)", script.string()));
  scratch.renameOverTarget();
  fmt::print(stderr, "accuracy: wrote {}\n", (dir / "accuracy.png").string());
}

void runAccuracyCommand(const AccuracyCommandOptions& c) {
  AccuracyOptions o;
  o.scene = c.scene;
  const Scene scene = loadScene(c.scene);  // bad input fails before the output directory is made
  o.steps = c.quick ? std::vector<int>{5, 10, 30, 120} : c.steps;
  // Each solver with each integrator: XPBD's runs are "<solver>+xpbd", VBD's "<solver>+vbd" (cpu-xprev is
  // Verlet's x_prev form).
  o.solvers.clear();
  for (const std::string& integrator : c.integrators)
    for (const std::string& solver : c.solvers) {
      if (integrator == "verlet")
        o.solvers.push_back(solver);
      else if (solver != "cpu-xprev")
        o.solvers.push_back(solver + "+" + integrator);
    }
  if (o.solvers.empty())
    throw CommandError(kExitBadInput, "--integrator " + c.integrators.front() +
                                          ": cpu-xprev is Verlet's x_prev form; name another --solver");
  o.stretch_passes = c.quick ? std::vector<int>{scene.sim.stretch_passes} : c.passes;
  o.times = c.quick ? std::vector<double>{0.5, 1} : c.times;
  o.reference_factor = c.quick ? 8 : c.reference_factor;
  o.jobs = c.jobs;
  const std::string stem = fs::path(c.scene).stem().string();
  const fs::path dir = c.out.empty() ? fs::path("out") / "accuracy" / stem : fs::path(c.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CommandError(kExitBadInput, fmt::format("--out: {}: {}", dir.string(), ec.message()));
  // Before the runs, which take minutes: every file written at the end (matplotlib writes the PNG).
  for (const char* name : {"accuracy.csv", "reference.csv", "accuracy.md", "accuracy.png"})
    checkOutputFile(dir / name);

  // The CSV files are rewritten (atomically) as each run finishes: a sweep stopped after an hour, by
  // Ctrl-C or a lost session, keeps every run it finished.
  const auto writeCsv = [&dir](const AccuracyReport& so_far) {
    writeFileAtomically((dir / "accuracy.csv").string(), accuracyCsv(so_far));
    writeFileAtomically((dir / "reference.csv").string(), referenceCsv(so_far));
  };
  const AccuracyReport report = runAccuracy(
      o,
      [](const std::string& line) {
        fmt::print(stderr, "accuracy {}\n", line);
        std::fflush(stderr);
      },
      writeCsv);
  writeFileAtomically((dir / "accuracy.csv").string(), accuracyCsv(report));
  writeFileAtomically((dir / "reference.csv").string(), referenceCsv(report));
  writeFileAtomically((dir / "accuracy.md").string(), accuracyMarkdown(report));
  fmt::print(stderr, "accuracy: wrote {} and {} ({:.0f} s)\n", (dir / "accuracy.csv").string(),
             (dir / "accuracy.md").string(), report.wall_s);
  if (!c.no_plot) plot(dir, stem);
}

}  // namespace

void addAccuracyCommand(CLI::App& app) {
  auto c = std::make_shared<AccuracyCommandOptions>();
  CLI::App* cmd = app.add_subcommand("accuracy", "Error against run time, against a converged double-precision run");
  cmd->add_option("scene", c->scene, "Scene JSON file")->required();
  cmd->add_option("--out", c->out, "Output directory (default out/accuracy/<scene>)");
  addListOption(cmd, "--steps", c->steps, "Comma-separated substeps per frame")->check(integerIn(1, kMaxStepsPerFrame));
  addListOption(cmd, "--solver", c->solvers, "Comma-separated solvers")->check(CLI::IsMember(solverNames(true)));
  addListOption(cmd, "--integrator", c->integrators, "Comma-separated integrators, each a curve per solver")
      ->check(CLI::IsMember(integratorNames()));
  addListOption(cmd, "--passes", c->passes, "Comma-separated stretch-limit passes")
      ->check(integerIn(0, kMaxStretchPasses));
  addListOption(cmd, "--times", c->times, "Comma-separated sample times, s")->check(positiveNumberUpTo(kMaxSampleTime));
  cmd->add_option("--reference-factor", c->reference_factor, "Reference substeps = this x the scene's")
      ->check(CLI::Range(2, 256))
      ->capture_default_str();
  cmd->add_flag("--quick", c->quick,
                "Minutes instead of an hour on a 2-core machine with self-collision: substeps 5,10,30,120, the "
                "scene's stretch passes, t = 0.5, 1 s, reference x8 checked against x16");
  cmd->add_option("--jobs", c->jobs,
                  "CPU runs side by side, each on its share of the cores (0: one per core); GPU runs one at a time")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_flag("--no-plot", c->no_plot, "Write the CSV and markdown only");
  cmd->callback([c] { runAccuracyCommand(*c); });
}

}  // namespace drape
