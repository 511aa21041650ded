// The bench's logic on tiny CPU runs: resampling, order statistics, the bench's JSON (accuracy_test.cpp has
// the accuracy report's and the stability cases'). No GL: GPU solvers are not asked for.
#include "app/bench.hpp"
#include "app/command_error.hpp"
#include "core/derived.hpp"
#include "core/stability.hpp"
#include "test_paths.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <set>

namespace drape {
namespace {

std::string scenePath(const std::string& name) {
  return std::string(drape::test::sourceDir()) + "/scenes/" + name;
}

TEST(Resample, KeepsSizeMassAndCornerPins) {
  const Scene scene = loadScene(scenePath("pinned4.json"));
  for (int n : {2, 3, 16, 37, 256}) {
    const Scene s = resampleCloth(scene, n);
    EXPECT_EQ(s.cloth.num_width_points, n);
    EXPECT_EQ(s.cloth.num_height_points, n);
    EXPECT_EQ(s.cloth.width, scene.cloth.width);
    EXPECT_EQ(s.cloth.height, scene.cloth.height);
    EXPECT_EQ(s.cloth.density, scene.cloth.density);
    EXPECT_NEAR(derived::pointMass(s.cloth) * n * n, derived::pointMass(scene.cloth) * scene.cloth.pointCount(), 1e-9);
    const std::set<std::pair<int, int>> pins = [&] {
      std::set<std::pair<int, int>> out;
      for (glm::ivec2 p : s.cloth.pinned)
        out.insert({p.x, p.y});
      return out;
    }();
    EXPECT_EQ(pins, (std::set<std::pair<int, int>>{{0, 0}, {0, n - 1}, {n - 1, 0}, {n - 1, n - 1}})) << n;
    EXPECT_LT(2.0 * s.cloth.thickness, s.cloth.width / (n - 1)) << "neighbours at rest would self-collide";
    EXPECT_LE(s.cloth.thickness, scene.cloth.thickness);
  }
}

// bench --keep-thickness: a CS184 file refined as it is, its thickness kept, so that neighbours are held at rest.
TEST(Resample, KeepsTheThicknessWhenAsked) {
  const Scene scene = loadScene(scenePath("pinned2.json"));
  const Scene kept = resampleCloth(scene, 256, true), thinned = resampleCloth(scene, 256);
  EXPECT_EQ(kept.cloth.thickness, scene.cloth.thickness);
  EXPECT_GT(2.0 * kept.cloth.thickness, kept.cloth.width / 255) << "a 256 x 256 pinned2 holds its neighbours";
  EXPECT_LT(thinned.cloth.thickness, scene.cloth.thickness);
  EXPECT_EQ(resampleCloth(scene, 50, true).cloth.thickness, scene.cloth.thickness);
}

TEST(Resample, MergesPinsThatLandOnOnePoint) {
  Scene scene = loadScene(scenePath("pinned2.json"));
  scene.cloth.pinned = {{0, 0}, {1, 0}, {2, 0}, {49, 0}};
  const Scene s = resampleCloth(scene, 4);
  EXPECT_EQ(s.cloth.pinned.size(), 2u);  // 0, 1, 2 of 50 all land on 0 of 4
}

TEST(Summarize, OrderStatistics) {
  const Spread odd = summarize({5.0, 1.0, 3.0});
  EXPECT_EQ(odd.samples, 3);
  EXPECT_EQ(odd.median, 3.0);
  EXPECT_EQ(odd.min, 1.0);
  EXPECT_EQ(odd.max, 5.0);
  EXPECT_EQ(odd.q1, 2.0);
  EXPECT_EQ(odd.q3, 4.0);
  const Spread even = summarize({4.0, 1.0, 2.0, 3.0});
  EXPECT_EQ(even.median, 2.5);
  EXPECT_EQ(summarize({}).samples, 0);
}

TEST(Bench, TinyRunHasEveryFigure) {
  BenchOptions o;
  o.scenes = {scenePath("pinned4.json")};
  o.sizes = {6, 8};
  o.solvers = {"cpu", "cpu64"};
  o.frames = 2;
  o.warmup = 1;
  o.repeats = 2;
  int lines = 0;
  const BenchReport report = runBench(o, [&](const std::string&) { ++lines; });
  ASSERT_EQ(report.runs.size(), 4u);
  EXPECT_EQ(lines, 4);
  EXPECT_FALSE(report.gl.has_value());  // no GPU solver asked for
  for (const BenchRun& run : report.runs) {
    EXPECT_EQ(run.skipped, "");
    EXPECT_EQ(run.blew_up, "");
    EXPECT_EQ(run.points, (long long)run.size * run.size);
    EXPECT_EQ(run.frame_ms.samples, 2);
    EXPECT_GT(run.frame_ms.median, 0.0);
    EXPECT_LE(run.frame_ms.min, run.frame_ms.median);
    EXPECT_LE(run.frame_ms.median, run.frame_ms.max);
    EXPECT_DOUBLE_EQ(run.vertex_substeps_per_s,
                     double(run.points) * run.steps_per_frame / (run.frame_ms.median * 1e-3));
    EXPECT_EQ(run.gpu_memory_bytes, -1);
    std::vector<std::string> names;
    double pass_ms = 0;
    for (const BenchPass& p : run.passes) {
      names.push_back(p.name);
      EXPECT_EQ(p.calls_per_frame, run.steps_per_frame) << p.name;  // one call per substep
      EXPECT_GE(p.ms_per_frame, 0.0);
      pass_ms += p.ms_per_frame;
    }
    EXPECT_GT(pass_ms, 0.0) << "bench times the CPU's passes";
    EXPECT_EQ(names, (std::vector<std::string>{"forces", "integrate", "limit_stretch"}));
  }
  const nlohmann::json j = benchJson(report);
  for (const char* key : {"machine", "gl", "settings", "runs", "started_at", "wall_s"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["gl"].is_null());
  EXPECT_EQ(j["machine"]["logical_cores"].get<int>(), report.machine.logical_cores);
  EXPECT_FALSE(j["machine"]["cpu_model"].get<std::string>().empty());
  ASSERT_EQ(j["runs"].size(), 4u);
  for (const auto& run : j["runs"]) {
    for (const char* key : {"scene",
                            "solver",
                            "size",
                            "points",
                            "steps_per_frame",
                            "frame_ms",
                            "repeat_ms",
                            "passes",
                            "vertex_substeps_per_s",
                            "dispatches_per_frame",
                            "dispatches_per_substep",
                            "gpu_memory_bytes",
                            "pass_timing",
                            "sync_readbacks_per_frame",
                            "fence_waits_per_frame",
                            "bytes_per_point_substep",
                            "achieved_gbs",
                            "blew_up",
                            "stability_number",
                            "frames_per_repeat"})
      EXPECT_TRUE(run.contains(key)) << key;
    for (const char* key : {"median", "min", "max", "q1", "q3", "samples"})
      EXPECT_TRUE(run["frame_ms"].contains(key));
  }
  const std::string md = benchMarkdown(report);
  EXPECT_EQ(std::count(md.begin(), md.end(), '\n'), 2 + 1 + 2 + 4);  // two lines, blank, header, rule, runs
}

// A CPU run says how many of its substeps ran on a team: none on one thread; on two, a mid-sized cloth's
// trial decides (so any share), and team_threads is the way most of them ran.
TEST(Bench, ACpuRunSaysHowManySubstepsRanOnATeam) {
  BenchOptions o;
  o.scenes = {scenePath("pinned4.json")};
  o.sizes = {40};  // 1600 points: a trial's size
  o.solvers = {"cpu"};
  o.threads = {1, 2};
  o.frames = 2;
  o.warmup = 1;
  o.repeats = 1;
  const BenchReport report = runBench(o);
  ASSERT_EQ(report.runs.size(), 2u);
  const nlohmann::json j = benchJson(report);
  for (std::size_t r = 0; r < 2; ++r) {
    const BenchRun& run = report.runs[r];
    ASSERT_EQ(run.threads, int(r) + 1);
    EXPECT_GE(run.team_share, 0.0);
    EXPECT_LE(run.team_share, 1.0);
    EXPECT_EQ(run.team_threads, run.team_share >= 0.5 ? run.threads : 1) << "the way most substeps ran";
    EXPECT_DOUBLE_EQ(j["runs"][r]["cpu"]["team_share"].get<double>(), run.team_share);
    // The trial's last probe, where one ran: a time ratio, so positive; none on one thread.
    const nlohmann::json& ratio = j["runs"][r]["cpu"]["team_over_solo"];
    if (r == 0) {
      EXPECT_TRUE(ratio.is_null());
    } else if (!ratio.is_null()) {
      EXPECT_GT(ratio.get<double>(), 0.0);
    }
  }
  EXPECT_EQ(report.runs[0].team_share, 0.0) << "one thread has no team";
}

// `drape bench --team always`: a cloth of a trial's size runs every timed substep on the team, none decided.
TEST(Bench, TeamAlwaysRunsEverySubstepOnTheTeam) {
  BenchOptions o;
  o.scenes = {scenePath("pinned4.json")};
  o.sizes = {40};
  o.solvers = {"cpu"};
  o.threads = {2};
  o.team_always = true;
  o.frames = 2;
  o.warmup = 1;
  o.repeats = 1;
  const BenchReport report = runBench(o);
  ASSERT_EQ(report.runs.size(), 1u);
  EXPECT_EQ(report.runs[0].team_share, 1.0);
  EXPECT_EQ(report.runs[0].team_threads, 2);
  EXPECT_TRUE(benchJson(report)["runs"][0]["cpu"]["team_over_solo"].is_null()) << "no trial";
}

// --auto-substeps: a resampled cloth beyond the stability bound (pinned2 at 256², 1.62 against 1.41 at 30
// substeps) runs at the fewest substeps inside it, and not blowing up is the point; one inside keeps its 30.
TEST(Bench, AutoSubstepsBringsAFineClothInsideTheBound) {
  BenchOptions o;
  o.scenes = {scenePath("pinned2.json")};
  o.sizes = {16, 256};
  o.solvers = {"cpu"};
  o.frames = 1;
  o.warmup = 0;
  o.repeats = 1;
  const BenchReport plain = runBench(o);
  o.auto_substeps = true;
  const BenchReport raised = runBench(o);
  ASSERT_EQ(plain.runs.size(), 2u);
  ASSERT_EQ(raised.runs.size(), 2u);
  EXPECT_EQ(raised.runs[0].steps_per_frame, plain.runs[0].steps_per_frame) << "16² is inside the bound already";
  EXPECT_FALSE(plain.runs[1].inside_bound);
  EXPECT_TRUE(raised.runs[1].inside_bound);
  EXPECT_GT(raised.runs[1].steps_per_frame, plain.runs[1].steps_per_frame);
  // The fewest: one substep less would be outside again
  EXPECT_FALSE(checkStability(withSubsteps(resampleCloth(loadScene(scenePath("pinned2.json")), 256, false),
                                           raised.runs[1].steps_per_frame - 1))
                   .ok);
  EXPECT_TRUE(benchJson(raised)["settings"]["auto_substeps"].get<bool>());
}

// The share-of-peak column knows a GPU by a name in its renderer string, the more specific name first,
// and nothing else: llvmpipe's "memory" is the CPU's.
TEST(Bench, PeakBandwidthByRendererName) {
  EXPECT_EQ(knownPeakGbs("NVIDIA H200/PCIe/SSE2"), 4800.0);
  EXPECT_EQ(knownPeakGbs("NVIDIA H100 PCIe/PCIe/SSE2"), 2000.0);
  EXPECT_EQ(knownPeakGbs("NVIDIA H100 80GB HBM3/PCIe/SSE2"), 3350.0);
  EXPECT_EQ(knownPeakGbs("llvmpipe (LLVM 15.0.6, 256 bits)"), 0.0);
}

// A bench JSON reads back as the runs it holds, and the before/after table pairs each run with the
// baseline's run of the same scene, size and solver, pass by pass, with the ratio of the frame times.
TEST(Bench, BaselineComparisonPairsRunsAndPasses) {
  BenchOptions o;
  o.scenes = {scenePath("pinned4.json")};
  o.sizes = {6};
  o.solvers = {"cpu"};
  o.threads = {1, 2};
  o.frames = 2;
  o.warmup = 0;
  o.repeats = 1;
  const BenchReport report = runBench(o);
  const std::vector<BenchRun> read = benchRunsFromJson(benchJson(report));
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].threads, 2);
  EXPECT_EQ(read[0].frame_ms.median, report.runs[0].frame_ms.median);
  ASSERT_EQ(read[0].passes.size(), report.runs[0].passes.size());
  EXPECT_EQ(read[0].passes[2].name, "limit_stretch");

  // A baseline from an older binary: one thread (no "threads" key), twice as slow, a pass since renamed.
  nlohmann::json old = benchJson(report);
  old["runs"].erase(1);
  old["runs"][0].erase("threads");
  old["runs"][0]["frame_ms"]["median"] = 2 * report.runs[0].frame_ms.median;
  old["runs"][0]["passes"][0]["name"] = "old_forces";
  const std::string md = benchComparisonMarkdown(report, benchRunsFromJson(old), "old.json");
  EXPECT_NE(md.find("old.json"), std::string::npos);
  for (const char* solver : {"cpu ×1", "cpu ×2"}) {
    EXPECT_NE(md.find(fmt::format("| pinned4 | 6 | {} | **frame** |", solver)), std::string::npos) << md;
    EXPECT_NE(md.find(fmt::format("| pinned4 | 6 | {} | old_forces |", solver)), std::string::npos) << md;
    EXPECT_NE(md.find(fmt::format("| pinned4 | 6 | {} | forces |", solver)), std::string::npos) << md;
  }
  EXPECT_NE(md.find("| **0.50** |"), std::string::npos) << "the ×1 run against a baseline twice as slow:\n" << md;

  nlohmann::json bad = old;
  bad["runs"][0].erase("size");
  try {
    benchRunsFromJson(bad);
    FAIL() << "a run without its size must not read";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "runs[0].size: missing or not an integer");
  }
  EXPECT_THROW(benchRunsFromJson(nlohmann::json::object()), std::runtime_error);
}

// Every value the comparison reads is checked: a size beyond an int used to wrap, a negative time compared.
TEST(Bench, BaselineValuesOutOfRangeAreRefusedNamingTheKey) {
  const nlohmann::json good = nlohmann::json::parse(R"({"runs": [{"scene": "a.json", "solver": "cpu", "size": 8,
    "frame_ms": {"median": 1.5, "samples": 3}, "passes": [{"name": "forces", "ms_per_frame": 0.5}]}]})");
  ASSERT_EQ(benchRunsFromJson(good).at(0).passes.at(0).ms_per_frame, 0.5);
  const std::pair<nlohmann::json::json_pointer, nlohmann::json> bad[] = {
      {"/runs/0/size"_json_pointer, 99999999999},
      {"/runs/0/size"_json_pointer, -3},
      {"/runs/0/threads"_json_pointer, 5000},
      {"/runs/0/frame_ms/median"_json_pointer, -1},
      {"/runs/0/frame_ms/samples"_json_pointer, 0.5},
      {"/runs/0/passes/0/ms_per_frame"_json_pointer, "x"},
      {"/runs/0/skipped"_json_pointer, 3},
      {"/runs/0/frame_ms"_json_pointer, 7}};
  const char* expected[] = {"runs[0].size: 99999999999 is out of range (2 to 2048)",
                            "runs[0].size: -3 is out of range (2 to 2048)",
                            "runs[0].threads: 5000 is out of range (0 to 1024)",
                            "runs[0].frame_ms.median: -1 is not a number >= 0",
                            "runs[0].frame_ms.samples: missing or not an integer",
                            "runs[0].passes[0].ms_per_frame: missing or not a number",
                            "runs[0].skipped: missing or not a string",
                            "runs[0].frame_ms: not an object"};
  for (std::size_t i = 0; i < std::size(bad); ++i) {
    nlohmann::json j = good;
    j[bad[i].first] = bad[i].second;
    try {
      benchRunsFromJson(j);
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), expected[i]);
    }
  }
}

// --integrator verlet,xpbd: both integrators at every size, a run each, the scene's own when none is asked.
TEST(Bench, EachIntegratorIsARunOfItsOwn) {
  BenchOptions o;
  o.scenes = {scenePath("pinned4.json")};
  o.sizes = {6, 8};
  o.solvers = {"cpu"};
  o.frames = 1;
  o.warmup = 0;
  o.repeats = 1;
  o.integrators = {"verlet", "xpbd"};
  const BenchReport both = runBench(o);
  ASSERT_EQ(both.runs.size(), 4u);
  const std::vector<std::pair<int, std::string>> expected = {{6, "verlet"}, {6, "xpbd"}, {8, "verlet"}, {8, "xpbd"}};
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(both.runs[k].size, expected[k].first) << k;
    EXPECT_EQ(both.runs[k].integrator, expected[k].second) << k;
  }
  EXPECT_NE(both.runs[0].passes.size(), both.runs[1].passes.size()) << "XPBD runs a pass of its own";
  EXPECT_EQ(benchJson(both)["settings"]["integrators"], nlohmann::json({"verlet", "xpbd"}));
  o.integrators.clear();
  const BenchReport own = runBench(o);
  ASSERT_EQ(own.runs.size(), 2u);
  EXPECT_EQ(own.runs[0].integrator, "verlet");  // pinned4.json names none: Verlet
  EXPECT_TRUE(benchJson(own)["settings"]["integrators"].is_null());
}

TEST(Bench, UnknownSolverIsBadInput) {
  SolverFactory factory;
  try {
    factory.make(loadScene(scenePath("pinned4.json")), "cuda");
    FAIL();
  } catch (const CommandError& e) {
    EXPECT_EQ(e.status(), kExitBadInput);
  }
}

}  // namespace
}  // namespace drape
