// `drape bench`: ms per frame and per pass, vertex-substeps per second, dispatches per frame and GPU
// memory for each scene x cloth size x solver; JSON for comparing runs, markdown for the README.
#include "app/bench.hpp"
#include "app/commands.hpp"
#include "app/options.hpp"
#include "app/output.hpp"
#include "app/roofline.hpp"
#include "core/data_dir.hpp"
#include "core/input_file.hpp"
#include "gl/context.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace drape {

namespace {

const std::vector<std::string> kDefaultScenes = {"scenes/pinned2.json", "scenes/sphere.json"};

struct BenchCommandOptions {
  std::vector<std::string> scenes = kDefaultScenes;
  std::vector<int> sizes = {32, 64, 128, 256};
  std::vector<std::string> solvers = {"cpu", "gpu"};
  std::vector<int> threads = {0};
  std::string team = "auto";
  int frames = 5;
  int warmup = 2;
  int repeats = 3;
  double budget_s = 10;
  double peak_gbs = 0;
  std::string json;
  std::string markdown;
  std::string baseline;
  std::vector<std::string> integrators;  // empty: each scene's
  bool roofline = false;
  bool keep_thickness = false;
  bool auto_substeps = false;
};

// Far beyond any bench --json (a few hundred KB for the largest sweep).
constexpr long long kMaxBaselineBytes = 64LL * 1024 * 1024;

// An earlier `drape bench --json` to compare with; read before the runs so a bad file costs nothing.
std::vector<BenchRun> readBaseline(const std::string& path) {
  std::string text;
  try {
    text = readInputFile(path, kMaxBaselineBytes, "a bench --json file");
  } catch (const InputError& e) {
    throw CommandError(kExitBadInput, fmt::format("--baseline: {}: {}", path, e.what()));
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded()) throw CommandError(kExitBadInput, fmt::format("--baseline: {}: not valid JSON", path));
  try {
    return benchRunsFromJson(j);
  } catch (const std::runtime_error& e) {
    throw CommandError(kExitBadInput, fmt::format("--baseline: {}: {}", path, e.what()));
  }
}

// Without a context every GPU run would be skipped and the command would look like a success: fail
// before any work instead (status 3), as --solver gpu does everywhere else.
void requireGlIfAsked(const std::vector<std::string>& solvers) {
  if (std::none_of(solvers.begin(), solvers.end(), isGpuSolver)) return;
  try {
    [[maybe_unused]] const gl::HeadlessContext probe = gl::HeadlessContext::create();
  } catch (const gl::ContextError& e) {
    throw CommandError(kExitNoGl, fmt::format("bench: --solver gpu: no OpenGL 4.5 context ({}); --solver cpu "
                                              "benches the CPU solvers only",
                                              e.what()));
  }
}

void runBenchCommand(const BenchCommandOptions& c) {
  BenchOptions o;
  o.scenes = c.scenes;
  // The default scenes are found from any directory; scenes the user names are taken as given.
  if (c.scenes == kDefaultScenes)
    for (std::string& path : o.scenes)
      if (!std::filesystem::exists(path)) path = (dataDir("scenes") / std::filesystem::path(path).filename()).string();
  o.sizes = c.sizes;
  o.solvers = c.solvers;
  o.threads = c.threads;
  o.team_always = c.team == "always";
  o.frames = c.frames;
  o.warmup = c.warmup;
  o.repeats = c.repeats;
  o.budget_s = c.budget_s;
  o.peak_gbs = c.peak_gbs;
  o.integrators = c.integrators;
  o.roofline = c.roofline;
  o.keep_thickness = c.keep_thickness;
  o.auto_substeps = c.auto_substeps;
  // Output paths are checked before the runs, which may take minutes, not after them.
  if (!c.json.empty()) checkOutputFile(c.json);
  if (!c.markdown.empty()) checkOutputFile(c.markdown);
  const std::vector<BenchRun> baseline = c.baseline.empty() ? std::vector<BenchRun>{} : readBaseline(c.baseline);
  requireGlIfAsked(o.solvers);
  const BenchReport report = runBench(o, [](const std::string& line) {
    fmt::print(stderr, "bench {}\n", line);
    std::fflush(stderr);
  });
  const std::string json = benchJson(report).dump(2) + "\n";
  if (!c.json.empty()) writeFileAtomically(c.json, json);
  if (!c.markdown.empty())
    writeFileAtomically(c.markdown,
                        benchMarkdown(report) +
                            (c.baseline.empty() ? "" : "\n" + benchComparisonMarkdown(report, baseline, c.baseline)) +
                            (c.roofline ? "\n" + rooflineMarkdown(report) : ""));
  if (c.roofline && c.markdown.empty()) fmt::print(stderr, "{}", rooflineMarkdown(report));
  if (c.json.empty()) fmt::print("{}", json);
  fmt::print(stderr, "bench: {} runs in {:.1f} s\n", report.runs.size(), report.wall_s);
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto c = std::make_shared<BenchCommandOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Time the solvers on scenes resampled to N x N cloths");
  addListOption(cmd, "--scenes", c->scenes, "Comma-separated scene files");
  addListOption(cmd, "--sizes", c->sizes, "Comma-separated cloth sizes N (N x N points)")
      ->check(integerIn(2, int(std::sqrt(double(kMaxClothPoints)))));
  addListOption(cmd, "--solver", c->solvers, "Comma-separated solvers")->check(CLI::IsMember(solverNames(true)));
  addListOption(cmd, "--threads", c->threads,
                "Comma-separated thread counts for the CPU solvers, a run each (0 = every core)")
      ->check(integerIn(0, 1024));
  cmd->add_option("--team", c->team,
                  "CPU solvers with several threads: auto (below 32768 points the solver times a team against one "
                  "thread as it runs) or always (every substep on the team)")
      ->check(CLI::IsMember({"auto", "always"}))
      ->capture_default_str();
  cmd->add_option("--frames", c->frames, "Timed frames per repeat, at most")->check(kPositive)->capture_default_str();
  cmd->add_option("--warmup", c->warmup, "Untimed frames before timing")->check(kNonNegative)->capture_default_str();
  cmd->add_option("--repeats", c->repeats, "Timed repeats (median and spread over these)")
      ->check(kPositive)
      ->capture_default_str();
  cmd->add_option("--budget", c->budget_s, "Timed seconds per run: slow runs time fewer frames per repeat")
      ->check(kPositive)
      ->capture_default_str();
  cmd->add_option("--peak-gbs", c->peak_gbs,
                  "The GPU's peak memory bandwidth in GB/s, for the share-of-peak column (unset: known GPUs by name)")
      ->check(kPositive)
      ->default_str("");  // 0 stands for unset
  addListOption(
      cmd, "--integrator", c->integrators,
      "Comma-separated integrators (verlet, xpbd, vbd), a run each; default: the scene's simulation.integrator")
      ->check(CLI::IsMember(integratorNames()));
  cmd->add_flag("--roofline", c->roofline,
                "Probe this machine's peak (memory and L2 bandwidth, vector arithmetic, a barrier) first; the markdown "
                "adds each CPU pass's work a point and its share of the least time the peak allows");
  cmd->add_flag("--keep-thickness", c->keep_thickness,
                "Keep each scene's cloth thickness at every size (default: at most 0.45 x the spacing, so that no "
                "two points are in self-collision range at rest); a fine cloth then has neighbours the springs hold");
  cmd->add_flag("--auto-substeps", c->auto_substeps,
                "Where a resampled scene is beyond the stability bound, the fewest substeps per frame inside it (as "
                "simulate --auto-substeps), so that large sizes run instead of blowing up");
  cmd->add_option("--json", c->json, "Write the results as JSON here (default: stdout)");
  cmd->add_option("--markdown", c->markdown, "Write a markdown table of the results here");
  cmd->add_option(
      "--baseline", c->baseline,
      "An earlier bench --json (e.g. of an older binary): the markdown adds per-pass times before and after");
  cmd->callback([c] { runBenchCommand(*c); });
}

}  // namespace drape
