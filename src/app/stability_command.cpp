// `drape stability`: stiff and extreme cases at several substep counts, with and without the stability
// guard; a markdown table and a CSV.
#include "app/commands.hpp"
#include "app/measure.hpp"
#include "app/options.hpp"
#include "app/output.hpp"
#include "app/progress.hpp"
#include "app/stability_cases.hpp"
#include "app/stability_summary.hpp"

#include <fmt/core.h>
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

namespace drape {

namespace {

namespace fs = std::filesystem;

struct StabilityCommandOptions {
  std::string out = "out/stability";
  std::vector<int> steps = {1, 5, 30, 120};
  std::vector<int> implicit_steps = {1, 5, 30};
  std::string integrator;          // empty: all three
  std::vector<std::string> cases;  // empty: all
  int jobs = 0;                    // runs side by side; 0: one per core
};

void runStabilityCommand(const StabilityCommandOptions& o) {
  const std::vector<StabilityCase> all = stabilityCases();
  std::vector<StabilityCase> chosen = o.cases.empty() ? all : std::vector<StabilityCase>{};
  for (const std::string& name : o.cases)
    for (const StabilityCase& c : all)
      if (c.name == name) chosen.push_back(c);
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw CommandError(kExitBadInput, fmt::format("--out: {}: {}", o.out, ec.message()));
  for (const char* name : {"stability.csv", "stability.md"})
    checkOutputFile(fs::path(o.out) / name);  // before the runs, not after them
  const StabilityReport report = runStability(
      chosen, !o.integrator.empty() && o.integrator != "verlet" ? std::vector<int>{} : o.steps,
      [](const std::string& line) {
        fmt::print(stderr, "stability {}\n", line);
        std::fflush(stderr);
      },
      o.jobs, o.integrator == "verlet" ? std::vector<int>{} : o.implicit_steps,
      o.integrator == "xpbd"  ? std::vector<Integrator>{Integrator::Xpbd}
      : o.integrator == "vbd" ? std::vector<Integrator>{Integrator::Vbd}
                              : std::vector<Integrator>{Integrator::Xpbd, Integrator::Vbd});
  const fs::path dir(o.out);
  writeFileAtomically((dir / "stability.csv").string(), stabilityCsv(report));
  const std::string md = stabilityMarkdown(report, chosen);
  writeFileAtomically((dir / "stability.md").string(), md);
  // The short table here, the full one (every case, every run) in the file.
  std::size_t stable = 0;
  for (const StabilityResult& r : report.results)
    stable += r.stable;
  fmt::print("{} runs, {} stable, {} unstable, in {} ({} at a time); every case in {}\n\n{}", report.results.size(),
             stable, report.results.size() - stable, formatDuration(report.wall_s), report.jobs,
             (dir / "stability.md").string(), stabilitySummary(report, chosen));
  fmt::print(stderr, "stability: wrote {} and {}\n", (dir / "stability.csv").string(), (dir / "stability.md").string());
}

}  // namespace

void addStabilityCommand(CLI::App& app) {
  auto o = std::make_shared<StabilityCommandOptions>();
  CLI::App* cmd = app.add_subcommand("stability", "Stiff and extreme cases: stable or not, with and without the guard");
  cmd->add_option("--out", o->out, "Output directory")->capture_default_str();
  addListOption(cmd, "--steps", o->steps, "Comma-separated substeps per frame")->check(integerIn(1, kMaxStepsPerFrame));
  std::vector<std::string> names;
  for (const StabilityCase& c : stabilityCases())
    names.push_back(c.name);
  addListOption(cmd, "--cases", o->cases, "Comma-separated case names (default: all)")->check(CLI::IsMember(names));
  // --xpbd-steps: its name from before VBD, kept so existing command lines still run.
  addListOption(cmd, "--implicit-steps,--xpbd-steps", o->implicit_steps,
                "Comma-separated substeps per frame for the XPBD and VBD runs (no guard)")
      ->check(integerIn(1, kMaxStepsPerFrame));
  cmd->add_option("--integrator", o->integrator,
                  "Run only verlet (with its guard), only xpbd or only vbd (default: all)")
      ->check(CLI::IsMember(integratorNames()));
  cmd->add_option("--jobs", o->jobs, "Runs side by side, each on its share of the cores (0: one per core)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->callback([o] { runStabilityCommand(*o); });
}

}  // namespace drape
