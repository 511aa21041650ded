// What `drape stability` prints at the end (app/stability_summary.hpp): one row per integrator and substep
// count, with the guard's own rows, from a report made by hand.
#include "app/stability_summary.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace drape {
namespace {

StabilityCase ksCase(const char* name, double ks) {
  StabilityCase c;
  c.name = name;
  c.scene.cloth.ks = ks;
  c.sweeps_ks = true;
  return c;
}

StabilityResult result(const char* name, int steps, bool guarded, bool stable,
                       Integrator integrator = Integrator::Verlet, double max_strain = 0.05) {
  StabilityResult r;
  r.case_name = name;
  r.steps_asked = steps;
  r.steps_per_frame = guarded ? 96 : steps;
  r.guarded = guarded;
  r.stable = stable;
  r.first_bad_frame = stable ? -1 : 2;
  r.integrator = integrator;
  r.max_strain = max_strain;
  return r;
}

// Keeping its shape comes first: a stable run stretched past 20% (ks 1e2 at 5 substeps, 133% as measured)
// counts as stable and not as keeping it.
TEST(StabilitySummary, OneShortRowPerIntegratorAndSubstepCount) {
  const std::vector<StabilityCase> cases = {ksCase("ks-1e2", 1e2), ksCase("ks-1e6", 1e6)};
  StabilityReport report;
  report.steps = {5, 30};
  report.implicit_steps = {30};
  report.implicit = {Integrator::Xpbd};
  report.results = {result("ks-1e2", 5, false, true, Integrator::Verlet, 1.33),
                    result("ks-1e6", 5, false, false),
                    result("ks-1e6", 5, true, true),
                    result("ks-1e2", 30, false, true),
                    result("ks-1e6", 30, false, true, Integrator::Verlet, 1.63),
                    result("ks-1e2", 30, false, true, Integrator::Xpbd),
                    result("ks-1e6", 30, false, true, Integrator::Xpbd)};
  const std::string table = stabilitySummary(report, cases);
  EXPECT_NE(table.find("| verlet | 5 | 0 of 2 | 1 of 2 | none | 1e2 | ks-1e6 (2) |"), std::string::npos) << table;
  EXPECT_NE(table.find("| verlet | 5 (guard) | 1 of 2 | 2 of 2 | 1e6 | 1e6 | – |"), std::string::npos) << table;
  EXPECT_NE(table.find("| verlet | 30 | 1 of 2 | 2 of 2 | 1e2 | 1e6 | – |"), std::string::npos) << table;
  EXPECT_NE(table.find("| xpbd | 30 | 2 of 2 | 2 of 2 | 1e6 | 1e6 | – |"), std::string::npos) << table;
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 2 + 5) << table;
}

TEST(StabilitySummary, ARunCostsItsFramesSubstepsAndPoints) {
  StabilityCase c = ksCase("ks-1e2", 1e2);
  c.frames = 180;
  const double points = double(c.scene.cloth.num_width_points) * c.scene.cloth.num_height_points;
  EXPECT_EQ(stabilityRunCost(c, 30, false), 180.0 * 30 * points);
  c.scene.sim.integrator = Integrator::Vbd;
  EXPECT_EQ(stabilityRunCost(c, 30, false), 2 * 180.0 * 30 * points);
}

// Each finished run's line starts with the count and, but for the last, the time left.
TEST(StabilitySummary, EachRunsLineCountsAndEstimates) {
  StabilityCase c = ksCase("ks-1e2", 1e2);
  c.scene.cloth.num_width_points = c.scene.cloth.num_height_points = 8;
  c.frames = 3;
  std::vector<std::string> lines;
  const StabilityReport report = runStability(
      {c}, {1, 5}, [&](const std::string& line) { lines.push_back(line); }, 1);
  ASSERT_EQ(report.results.size(), 2u);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("1/2, ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(" left: ks-1e2 1 substeps: "), std::string::npos) << lines[0];
  EXPECT_EQ(lines[1].rfind("2/2, ", 0), 0u) << lines[1];
  EXPECT_EQ(lines[1].find(" left"), std::string::npos) << lines[1];
}

}  // namespace
}  // namespace drape
