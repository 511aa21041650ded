// The accuracy report's exact properties and the stability cases on tiny CPU runs (bench_test.cpp has the bench's).
// No GL: GPU solvers are not asked for.
#include "app/accuracy.hpp"
#include "app/jobs.hpp"
#include "app/stability_cases.hpp"
#include "core/stability.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

namespace drape {
namespace {

namespace fs = std::filesystem;

fs::path writeTinyScene() {
  const fs::path p = fs::temp_directory_path() / ("drape_bench_test_" + std::to_string(::getpid()) + ".json");
  std::ofstream(p) << R"({"cloth": {"width": 1, "height": 1, "num_width_points": 6, "num_height_points": 6,
    "thickness": 0.01, "orientation": 0, "pinned": [[0, 0], [5, 0]], "density": 15, "ks": 500, "damping": 0.2},
    "simulation": {"self_collision": false, "steps_per_frame": 4, "stretch_passes": 4}})";
  return p;
}

// A configuration equal to the reference (same solver, substeps and passes) has error exactly 0:
// the runs are deterministic and compared at the same frames.
TEST(Accuracy, ReferenceConfigurationHasZeroErrorAndRowsAreComplete) {
  const fs::path scene = writeTinyScene();
  AccuracyOptions o;
  o.scene = scene.string();
  o.reference_factor = 2;
  o.steps = {2, 8};
  o.solvers = {"cpu", "cpu64"};
  o.stretch_passes = {4};
  o.times = {0.05, 0.1};
  const AccuracyReport r = runAccuracy(o);
  ASSERT_EQ(r.references.size(), 1u);
  EXPECT_EQ(r.references[0].steps_per_frame, 8);
  EXPECT_EQ(r.references[0].check_steps_per_frame, 16);
  EXPECT_EQ(r.references[0].samples.size(), 2u);
  ASSERT_EQ(r.runs.size(), 4u);
  for (const AccuracyRun& run : r.runs) {
    EXPECT_EQ(run.unstable, "") << run.solver << " " << run.steps_per_frame;
    ASSERT_EQ(run.samples.size(), 2u);
    EXPECT_EQ(run.samples[0].frame, 5);  // 0.05 s at 90 frames/s, rounded
    EXPECT_EQ(run.samples[1].frame, 9);
    EXPECT_GT(run.ms_per_sim_s, 0.0);
    // Precision alone: cpu64 is its own twin; float differs from double at the same substeps.
    if (run.solver == "cpu64") {
      EXPECT_EQ(run.samples[1].vs_double, 0.0);
    } else {
      EXPECT_GT(run.samples[1].vs_double, 0.0);
    }
    if (run.solver == "cpu64" && run.steps_per_frame == 8) {
      EXPECT_EQ(run.samples[1].rms_error, 0.0);
      EXPECT_EQ(run.samples[1].max_error, 0.0);
    } else {
      EXPECT_GT(run.samples[1].rms_error, 0.0);
    }
  }
  const std::string csv = accuracyCsv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4 * 2);
  const std::string ref = referenceCsv(r);
  EXPECT_EQ(std::count(ref.begin(), ref.end(), '\n'), 1 + 2);
  fs::remove(scene);
}

// Runs side by side (--jobs) change nothing but the time: every figure but the timings equals the
// one-at-a-time sweep's, in the same order.
TEST(Accuracy, RunsSideBySideGiveTheSameReportAsOneAtATime) {
  const fs::path scene = writeTinyScene();
  AccuracyOptions o;
  o.scene = scene.string();
  o.reference_factor = 2;
  o.steps = {2, 4, 8};
  o.solvers = {"cpu", "cpu64", "cpu-xprev"};
  o.stretch_passes = {1, 4};
  o.times = {0.05, 0.1};
  o.jobs = 1;
  const AccuracyReport serial = runAccuracy(o);
  o.jobs = 3;
  const AccuracyReport parallel = runAccuracy(o);
  EXPECT_EQ(serial.jobs, 1);
  EXPECT_EQ(parallel.jobs, 3);
  EXPECT_EQ(parallel.threads_per_run, threadsPerJob(3));
  ASSERT_EQ(serial.runs.size(), 18u);
  ASSERT_EQ(parallel.runs.size(), serial.runs.size());
  for (std::size_t k = 0; k < serial.runs.size(); ++k) {
    const AccuracyRun &a = serial.runs[k], &b = parallel.runs[k];
    EXPECT_EQ(std::tie(a.solver, a.steps_per_frame, a.stretch_passes),
              std::tie(b.solver, b.steps_per_frame, b.stretch_passes));
    ASSERT_EQ(a.samples.size(), b.samples.size());
    for (std::size_t i = 0; i < a.samples.size(); ++i) {
      EXPECT_EQ(a.samples[i].rms_error, b.samples[i].rms_error) << a.solver << " " << a.steps_per_frame;
      EXPECT_EQ(a.samples[i].max_strain, b.samples[i].max_strain);
      EXPECT_EQ(a.samples[i].vs_double, b.samples[i].vs_double);
    }
  }
  ASSERT_EQ(serial.references.size(), parallel.references.size());
  for (std::size_t k = 0; k < serial.references.size(); ++k)
    EXPECT_EQ(serial.references[k].samples.back().rms_error, parallel.references[k].samples.back().rms_error);
  fs::remove(scene);
}

TEST(Accuracy, MarkdownShowsPenetrationOnlyWhereSomethingPenetrated) {
  AccuracyReport r;
  r.scene = "scenes/sphere.json";
  r.options.steps = {5};
  r.options.solvers = {"cpu"};
  r.options.stretch_passes = {1};
  r.options.times = {1};
  AccuracyRun run;
  run.solver = "cpu";
  run.steps_per_frame = 5;
  run.stretch_passes = 1;
  run.samples.push_back(ErrorSample{.t = 1, .frame = 90, .rms_error = 0.01});
  r.runs.push_back(run);
  EXPECT_EQ(accuracyMarkdown(r).find("penetration"), std::string::npos);
  r.runs[0].samples[0].penetration = 0.0025;  // m
  const std::string md = accuracyMarkdown(r);
  const std::size_t table = md.find("Deepest penetration into a collider, mm");
  ASSERT_NE(table, std::string::npos) << md;
  EXPECT_NE(md.find("| 5 | 2.5 |", table), std::string::npos) << md.substr(table);
}

// The order is the fitted slope of log(error) against log(substeps), over the runs the reference resolves.
TEST(Accuracy, ConvergenceOrderIsTheFittedSlopeOverResolvedRuns) {
  AccuracyReport r;
  r.options.steps = {5, 10, 20, 40, 80};
  r.options.solvers = {"cpu", "cpu+xpbd"};
  r.options.stretch_passes = {0};
  ReferenceCheck ref;
  ref.stretch_passes = 0;
  ref.samples.push_back(ErrorSample{.t = 1, .rms_error = 5e-5});
  r.references.push_back(ref);
  for (int steps : r.options.steps)
    for (const char* solver : {"cpu", "cpu+xpbd"}) {
      AccuracyRun run;
      run.solver = solver;
      run.steps_per_frame = steps;
      // cpu: second order, its 80-substep error (9.8e-5) below 4 times the reference's own and left out;
      // cpu+xpbd: first order, its 5-substep run unstable.
      const bool second = std::string(solver) == "cpu";
      const double error = second ? 0.025 * 25.0 / (steps * steps) : 0.02 * 5.0 / steps;
      run.samples.push_back(ErrorSample{.t = 0.5, .rms_error = error / 2});
      run.samples.push_back(ErrorSample{.t = 1, .rms_error = error});
      if (!second && steps == 5) run.unstable = "a spring is stretched";
      r.runs.push_back(run);
    }
  const ConvergenceOrder verlet = convergenceOrder(r, "cpu", 0);
  EXPECT_NEAR(verlet.order, 2.0, 1e-9);
  EXPECT_EQ(verlet.runs, 4);
  EXPECT_EQ(verlet.largest_steps, 40);
  const ConvergenceOrder xpbd = convergenceOrder(r, "cpu+xpbd", 0);
  EXPECT_NEAR(xpbd.order, 1.0, 1e-9);
  EXPECT_EQ(xpbd.runs, 4);
  EXPECT_EQ(xpbd.smallest_steps, 10);
  EXPECT_TRUE(std::isnan(convergenceOrder(r, "cpu", 1).order)) << "no runs with 1 stretch pass";
  const std::string md = accuracyMarkdown(r);
  EXPECT_NE(md.find("| 0 | 2.00 (4 runs, 5–40) | 1.00 (4 runs, 10–80) |"), std::string::npos) << md;
}

TEST(StabilityCases, EveryCaseOfTheIssueIsThere) {
  std::set<std::string> names;
  for (const StabilityCase& c : stabilityCases())
    names.insert(c.name);
  for (const char* name :
       {"ks-1e2", "ks-1e3", "ks-1e4", "ks-1e5", "ks-1e6", "ks-1e7", "density-1e0", "density-1e4", "damping-0",
        "damping-100", "heavy-two-pins", "jittered", "crumpled", "sphere-strike", "soak-10000"})
    EXPECT_EQ(names.count(name), 1u) << name;
}

TEST(StabilityCases, StartStatesAreDeterministicAndPinsStay) {
  for (const StabilityCase& c : stabilityCases()) {
    std::vector<glm::dvec3> x1, v1, x2, v2;
    startState(c, x1, v1);
    startState(c, x2, v2);
    EXPECT_EQ(x1, x2) << c.name;
    EXPECT_EQ(v1, v2) << c.name;
    const Topology topo = buildTopology(c.scene.cloth);
    for (glm::ivec2 p : c.scene.cloth.pinned) {
      const std::size_t i = std::size_t(p.y) * topo.W + p.x;
      EXPECT_EQ(x1[i], topo.initial_positions[i]) << c.name;
      EXPECT_EQ(v1[i], glm::dvec3(0)) << c.name;
    }
  }
}

TEST(StabilityCases, AnUnstableRunReportsItsFrame) {
  for (const StabilityCase& c : stabilityCases()) {
    if (c.name != "ks-1e7") continue;
    const StabilityResult plain = runStabilityCase(c, 1, false);
    EXPECT_FALSE(plain.inside_bound);
    EXPECT_FALSE(plain.stable);
    EXPECT_GE(plain.first_bad_frame, 1);
    EXPECT_EQ(plain.frames_run, plain.first_bad_frame);
    EXPECT_FALSE(plain.what.empty());
  }
}

TEST(StabilityCases, RunsSideBySideGiveTheSameResultsInTheSameOrder) {
  std::vector<StabilityCase> cases;
  for (const StabilityCase& c : stabilityCases())
    if (c.name == "ks-1e2" || c.name == "ks-1e6" || c.name == "jittered") cases.push_back(c);
  ASSERT_EQ(cases.size(), 3u);
  for (StabilityCase& c : cases)
    c.frames = std::min(c.frames, 30);
  const StabilityReport serial = runStability(cases, {1, 30}, {}, 1);
  const StabilityReport parallel = runStability(cases, {1, 30}, {}, 2);
  EXPECT_EQ(parallel.jobs, 2);
  ASSERT_EQ(serial.results.size(), parallel.results.size());
  EXPECT_GT(serial.results.size(), 6u) << "ks-1e6 at 1 and 30 substeps also runs with the guard";
  for (std::size_t k = 0; k < serial.results.size(); ++k) {
    const StabilityResult &a = serial.results[k], &b = parallel.results[k];
    EXPECT_EQ(std::tie(a.case_name, a.steps_asked, a.guarded, a.stable, a.first_bad_frame),
              std::tie(b.case_name, b.steps_asked, b.guarded, b.stable, b.first_bad_frame));
    EXPECT_EQ(a.max_strain, b.max_strain) << a.case_name;
    EXPECT_EQ(a.end_strain, b.end_strain) << a.case_name;
    if (a.stable) {
      EXPECT_LE(a.end_strain, a.max_strain) << a.case_name;
    }
    EXPECT_EQ(a.energy_end, b.energy_end) << a.case_name;
  }
}

// The summary reads the sweep as run: the largest stable ks, and any smaller one that was not stable.
TEST(StabilityCases, SummaryNamesLargestStableKs) {
  std::vector<StabilityCase> cases;
  for (const StabilityCase& c : stabilityCases())
    if (c.sweeps_ks) cases.push_back(c);
  ASSERT_EQ(cases.size(), 6u);
  StabilityReport report;
  report.steps = {5};
  for (const StabilityCase& c : cases) {
    StabilityResult r;
    r.case_name = c.name;
    r.steps_asked = r.steps_per_frame = 5;
    r.stable = c.name == "ks-1e3" || c.name == "ks-1e4";  // 1e2 unstable below them, 1e5.. above
    r.max_strain = c.name == "ks-1e4" ? 0.35 : 0.12;      // stable, but stretched out of shape
    report.results.push_back(r);
    if (c.scene.cloth.ks >= 1e5) {
      StabilityResult g = r;
      g.guarded = true;
      g.steps_per_frame = 50;
      g.stable = true;
      report.results.push_back(g);
    }
  }
  const std::string md = stabilityMarkdown(report, cases);
  EXPECT_NE(
      md.find("| 5 | 10000 (but not 100) | 1000 (but not 100) | 1e+07 (but not 100) | 1e+07 (but not 100, 10000) |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| ks-1e4 | 5 | 0 / 0 | yes | **no** |"), std::string::npos) << "stable, not in shape\n" << md;
  EXPECT_NE(stabilityCsv(report).find("\nks-1e4,verlet,5,0,5,0,0,1,1,0,-1,0,0.35,0,"), std::string::npos)
      << stabilityCsv(report);
  // Every row of a table has its header's columns.
  std::istringstream lines(md);
  std::size_t columns = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] != '|') {
      columns = 0;
      continue;
    }
    const auto bars = std::size_t(std::count(line.begin(), line.end(), '|'));
    if (columns == 0) columns = bars;
    EXPECT_EQ(bars, columns) << line;
  }
  EXPECT_EQ(findResult(report, "ks-1e6", 5, true)->steps_per_frame, 50);
  EXPECT_EQ(findResult(report, "ks-1e3", 5, true), nullptr);
}

}  // namespace
}  // namespace drape
