// A substep run by a team of threads gives one thread's bytes in every bundled scene, with every integrator,
// in float and double; and the team trial (cpu/team_trial.hpp) that decides whether a cloth below
// kTeamMinPoints gets a team picks the faster way by its measurements, probes again, and follows the
// machine when it changes.
#include "app/solver_factory.hpp"
#include "cpu/cpu_solver.hpp"
#include "cpu/team_trial.hpp"
#include "same_bytes.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <cmath>

#include <ostream>
#include <string>
#include <vector>

namespace drape {
namespace {

using test::sameBytes;

struct TeamCase {
  std::string scene;
  Integrator integrator;
};

// What ctest and a failure print for a case (not its bytes).
void PrintTo(const TeamCase& c, std::ostream* os) {
  *os << c.scene << " with " << integratorName(c.integrator);
}

std::vector<TeamCase> teamCases() {
  std::vector<TeamCase> cases;
  for (const std::string& name : test::bundledSceneNames())
    for (Integrator integrator : kIntegrators)
      cases.push_back({name, integrator});
  return cases;
}

class TeamBytes : public ::testing::TestWithParam<TeamCase> {};

template <class T>
void expectTeamGivesOneThreadsBytes(const Scene& scene, const char* what) {
  CpuSolver<T> one(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<T> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
  ASSERT_EQ(one.teamThreads(), 1);
  ASSERT_EQ(team.teamThreads(), 2);
  // Frames rather than substeps: a frame's passes (the flag's wind, the stretch limit's last pass) run too.
  for (int f = 0; f < 4; ++f) {
    one.stepFrame();
    team.stepFrame();
  }
  ASSERT_EQ(team.teamSubsteps(), team.substeps()) << what << ": every substep ran on the team";
  EXPECT_TRUE(sameBytes(one.positions(), team.positions())) << what;
  EXPECT_TRUE(sameBytes(one.displacements(), team.displacements())) << what;
}

TEST_P(TeamBytes, TwoThreadsGiveOneThreadsBytes) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + GetParam().scene + ".json");
  scene.sim.integrator = GetParam().integrator;
  expectTeamGivesOneThreadsBytes<float>(scene, "float");
  expectTeamGivesOneThreadsBytes<double>(scene, "double");
  // And self-collision the other way round from the file: its lists, stencil and sums on a team in every scene.
  scene.sim.self_collision = !scene.sim.self_collision;
  expectTeamGivesOneThreadsBytes<float>(scene, scene.sim.self_collision ? "float, self-collision on" : "float, off");
}

INSTANTIATE_TEST_SUITE_P(Bundled, TeamBytes, ::testing::ValuesIn(teamCases()),
                         [](const ::testing::TestParamInfo<TeamCase>& p) {
                           return p.param.scene + "_" + integratorName(p.param.integrator);
                         });

// CS184's selfCollision cloth on one thread and on a team of two, every substep on the team.
struct OneThreadAndTeam {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  CpuSolver<float> one{scene, CpuSolverOptions{.threads = 1}};
  CpuSolver<float> team{scene, CpuSolverOptions{.threads = 2, .team_min_points = 0}};
  void stepFrame() {
    one.stepFrame();
    team.stepFrame();
  }
};

// The bundled scenes' four frames end before most contact begins: the selfCollision cloth fallen and
// folding on the floor (frames 40 to 60: a few thousand pairs in range a substep).
TEST(TeamBytesContact, AFoldingClothOnATeamGivesOneThreadsBytes) {
  OneThreadAndTeam run;
  for (int f = 0; f < 60; ++f) {
    run.stepFrame();
    if (f < 40) continue;
    ASSERT_TRUE(sameBytes(run.one.positions(), run.team.positions())) << "frame " << f;
    ASSERT_TRUE(sameBytes(run.one.displacements(), run.team.displacements())) << "frame " << f;
    // The team builds the lists together (grid, entries, near and far parts): each point has the same partners in
    // each part (in the order its threads found them: the sums order their terms)
    const auto& a = run.one.collisionPairs();
    const auto& b = run.team.collisionPairs();
    ASSERT_EQ(a.rebuilds(), b.rebuilds()) << "frame " << f;
    for (const auto part : {&CollisionPairs<float>::nearEntries, &CollisionPairs<float>::farEntries}) {
      const auto &pa = (a.*part)(), &pb = (b.*part)();
      ASSERT_EQ(pa.start, pb.start) << "frame " << f;
      const auto sortedEntries = [](const CollisionPairs<float>::EntryPart& e) {
        std::vector<std::uint32_t> owner(e.owner.begin(), e.owner.begin() + e.start.back()),
            partner(e.partner.begin(), e.partner.begin() + e.start.back());
        for (std::size_t i = 0; i + 1 < e.start.size(); ++i)
          std::sort(partner.begin() + e.start[i], partner.begin() + e.start[i + 1]);
        return std::pair(owner, partner);
      };
      ASSERT_EQ(sortedEntries(pa), sortedEntries(pb)) << "frame " << f;
    }
  }
  EXPECT_EQ(run.team.teamSubsteps(), run.team.substeps());
  EXPECT_GT(run.one.pairTerms(), 100000) << "the cloth must be in contact with itself";
  EXPECT_GT(run.one.collisionPairs().rebuilds(), 20) << "the lists were built many times in the fold";
  // Every thread's terms are counted (`drape simulate -v` said one thread's share on a team).
  EXPECT_EQ(run.team.pairTerms(), run.one.pairTerms());
}

// Three threads on this machine's two cores: every barrier where a thread's core is taken ends asleep (the team's
// barrier spins 200 pauses, not 20,000, when its threads outnumber the processors), and the rows split unevenly.
TEST(TeamBytesContact, ATeamOfMoreThreadsThanCoresGivesOneThreadsBytesThroughTheFold) {
  const Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<float> team(scene, CpuSolverOptions{.threads = 3, .team_min_points = 0});
  ASSERT_EQ(team.teamThreads(), 3);
  for (int f = 0; f < 45; ++f) {
    one.stepFrame();
    team.stepFrame();
  }
  EXPECT_EQ(team.teamSubsteps(), team.substeps());
  EXPECT_TRUE(sameBytes(one.positions(), team.positions()));
  EXPECT_TRUE(sameBytes(one.displacements(), team.displacements()));
  EXPECT_GT(one.pairTerms(), 10000) << "the cloth must be in contact with itself";
  EXPECT_EQ(team.pairTerms(), one.pairTerms());
}

// A mid-sized cloth's trial moves substeps from the team to one thread and back. A list built on one
// thread after one built on the team must hold none of the team's pairs: they stayed in the second
// thread's share and were listed again, twice where they were still in range (two threads' runs of the
// selfCollision file differed from one thread's from the first contact).
TEST(TeamBytesContact, AListBuiltOnOneThreadAfterTheTeamHoldsOnlyItsOwnPairs) {
  OneThreadAndTeam run;
  for (int f = 0; f < 45; ++f)
    run.stepFrame();
  ASSERT_EQ(run.team.teamSubsteps(), run.team.substeps());
  ASSERT_TRUE(sameBytes(run.one.positions(), run.team.positions()));
  // The same state again makes both rebuild; the pass alone runs outside the team, its build on one thread.
  const std::vector<glm::dvec3> x(run.one.positions().begin(), run.one.positions().end()),
      v(run.one.displacements().begin(), run.one.displacements().end());
  run.one.setState(x, v);
  run.team.setState(x, v);
  run.one.selfCollide();
  run.team.selfCollide();
  EXPECT_EQ(run.team.collisionPairs().pairCount(), run.one.collisionPairs().pairCount());
  EXPECT_TRUE(sameBytes(run.one.positions(), run.team.positions()));
}

// Which thread finds and sums a point's pairs moves with the work (balanceShares): the bytes must not. Shares as
// uneven as the balance allows, either way round, through the fold.
TEST(TeamBytesContact, UnevenPairSharesGiveOneThreadsBytes) {
  for (const long long sixteenths : {1LL, 15LL}) {
    OneThreadAndTeam run;
    const auto n = (long long)run.one.positions().size();
    const std::vector<long long> shares = {0, n * sixteenths / 16, n};
    run.team.fixPairShares(shares);
    for (int f = 0; f < 50; ++f) {
      run.stepFrame();
      if (f < 40) continue;
      ASSERT_TRUE(sameBytes(run.one.positions(), run.team.positions())) << sixteenths << "/16, frame " << f;
      ASSERT_TRUE(sameBytes(run.one.displacements(), run.team.displacements())) << sixteenths << "/16, frame " << f;
    }
    EXPECT_EQ(run.team.pairShares(), shares) << "fixed";
    EXPECT_EQ(run.team.pairTerms(), run.one.pairTerms());
    EXPECT_GT(run.one.pairTerms(), 100000) << "the cloth must be in contact with itself";
  }
}

// The stretch limit's rows follow the time they take (GridPath::colourRows): where they are not the even split of
// the passes before and after, those passes' rows are another thread's, and the bytes must still be one thread's.
// Splits as uneven as a test can make them, either way round, with the limit (Verlet) and XPBD's sweeps.
TEST(TeamBytesLimit, UnevenColourRowsGiveOneThreadsBytes) {
  for (const Integrator integrator : {Integrator::Verlet, Integrator::Xpbd})
    for (const long long sixteenths : {1LL, 15LL}) {
      SCOPED_TRACE(::testing::Message() << integratorName(integrator) << ", " << sixteenths << "/16 of the rows");
      Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/pinned2.json");
      scene.sim.integrator = integrator;
      CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
      CpuSolver<float> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
      const long long h = scene.cloth.num_height_points;
      const std::vector<long long> rows = {0, h * sixteenths / 16, h};
      team.fixColourRows(rows);
      for (int f = 0; f < 20; ++f) {
        one.stepFrame();
        team.stepFrame();
      }
      ASSERT_EQ(team.colourRows(), rows) << "fixed";
      EXPECT_EQ(team.teamSubsteps(), team.substeps());
      EXPECT_TRUE(sameBytes(one.positions(), team.positions()));
      EXPECT_TRUE(sameBytes(one.displacements(), team.displacements()));
    }
}

// `simulate -v` says each thread's share of the work that follows its times at the end: the stretch limit's rows,
// self-collision's search and its sums (here fixed, uneven, so the figures are known).
TEST(TeamShares, VerboseOutputGivesEachThreadsShare) {
  const Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  const long long h = scene.cloth.num_height_points, n = h * scene.cloth.num_width_points;
  CpuSolver<float> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
  team.fixColourRows({0, h / 16, h});
  team.fixPairShares({0, n / 16, n}, {0, n - n / 16, n});
  team.stepFrame();
  const std::string said = describeThreads(team);
  EXPECT_NE(said.find("a team of 2 ran 30 of 30 substeps"), std::string::npos) << said;
  EXPECT_NE(said.find("the stretch limit's rows 6/94%"), std::string::npos) << said;
  EXPECT_NE(said.find("self-collision's search 94/6%"), std::string::npos) << said;
  EXPECT_NE(said.find("its sums 6/94%"), std::string::npos) << said;
  CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
  one.stepFrame();
  EXPECT_EQ(describeThreads(one), "") << "one thread: no team to describe";
}

// From kSplitTiles tiles a team splits the lists' check (boxes and comparisons of the tiles) between its
// threads: the same builds at the same substeps, so the same bytes.
TEST(TeamBytesLarge, ATeamSharesTheListCheckOfALargeCloth) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  scene.cloth.num_width_points = scene.cloth.num_height_points = 128;  // 16 x 16 tiles
  CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<float> team(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
  for (int s = 0; s < 150; ++s) {
    one.step();
    team.step();
    ASSERT_EQ(one.collisionPairs().rebuilds(), team.collisionPairs().rebuilds()) << "substep " << s;
  }
  EXPECT_GT(one.collisionPairs().rebuilds(), 1) << "the check found the lists stale at least once after the first";
  EXPECT_LT(one.collisionPairs().rebuilds(), 150) << "and valid at least once";
  EXPECT_TRUE(sameBytes(one.positions(), team.positions()));
  EXPECT_TRUE(sameBytes(one.displacements(), team.displacements()));
}

// spreadTeam moves each thread once and gives it back its whole mask (the same code on every thread of the team):
// the scheduler may still place it anywhere the process may run.
TEST(SpreadTeam, MovesEachThreadOnceAndKeepsTheMask) {
  cpu_set_t before, after;
  CPU_ZERO(&before);
  ASSERT_EQ(sched_getaffinity(0, sizeof before, &before), 0);
  const int processors = CPU_COUNT(&before);
  EXPECT_FALSE(spreadTeam(1)) << "one thread: nothing to spread";
  EXPECT_FALSE(spreadTeam(processors + 1)) << "more threads than processors";
  if (processors >= 2) {
    EXPECT_TRUE(spreadTeam(2));
  }
  CPU_ZERO(&after);
  ASSERT_EQ(sched_getaffinity(0, sizeof after, &after), 0);
  EXPECT_TRUE(CPU_EQUAL(&before, &after)) << "the calling thread keeps every processor it had";
}

// What a trial sees when one way takes `solo` seconds a substep and the other `team`: it runs n substeps
// and returns how many of them ran on the team.
long long runTrial(TeamTrial& trial, long long n, double solo, double team) {
  long long on_team = 0;
  for (long long s = 0; s < n; ++s) {
    const bool use = trial.useTeam();
    on_team += use;
    trial.record(use ? team : solo);
  }
  return on_team;
}

TEST(TeamTrial, KeepsTheTeamWhereItIsFaster) {
  TeamTrial trial;
  const long long n = 3000, on_team = runTrial(trial, n, 1.0, 0.75);
  EXPECT_TRUE(trial.useTeam());
  // Only the first substeps and the probes of one thread run alone.
  EXPECT_GT(on_team, n - 100);
  EXPECT_NEAR(trial.teamOverSolo(), 0.75, 1e-12);
}

TEST(TeamTrial, DropsTheTeamWhereItIsSlowerAndProbesItRarely) {
  TeamTrial trial;
  // A team twelve times slower: the 2-core machine with another job on a core.
  const long long n = 3000, on_team = runTrial(trial, n, 1.0, 12.0);
  EXPECT_FALSE(trial.useTeam());
  EXPECT_GT(on_team, 0);
  // A probe that has lost stops: a few substeps each, not kSamples.
  EXPECT_LT(on_team, 2 * 4);
  // What the probes cost, over the run's time: within kProbeShare once the run is long.
  const long long later = runTrial(trial, 20000, 1.0, 12.0);
  EXPECT_LT(double(later) * 11.0, 1.5 * TeamTrial::kProbeShare * 20000.0);
}

TEST(TeamTrial, AThousandTimesSlowerCostsLittleMoreThanTwelve) {
  TeamTrial trial;
  // Busy cores: each barrier waits a time slice. The intervals between probes grow with what they lost.
  const long long n = 200000, on_team = runTrial(trial, n, 1.0, 1000.0);
  EXPECT_FALSE(trial.useTeam());
  EXPECT_LT(double(on_team) * 999.0, 3 * TeamTrial::kProbeShare * double(n) + 3 * 1000.0);
}

TEST(TeamTrial, ASubstepThousandsOfTimesSlowerEndsTheProbeAtOnce) {
  TeamTrial trial;
  // The run's first team substep also starts the team's threads (the scheduler may hold one back for a time
  // slice): it does not end the first probe alone; the next does.
  EXPECT_EQ(runTrial(trial, 200, 1.0, 1600.0), 2) << "two substeps on the team, not three";
  EXPECT_FALSE(trial.useTeam());
  EXPECT_DOUBLE_EQ(trial.teamOverSolo(), 1600.0) << "what the second substep measured";
  // A later probe ends at its first such substep.
  EXPECT_EQ(runTrial(trial, 200000, 1.0, 1600.0), 1) << "one substep on the team, not two";
  TeamTrial quiet;
  // A substep interrupted for 50 times its time, on a team that is faster: not enough to end the probe.
  for (int s = 0; s < 200; ++s) {
    const bool use = quiet.useTeam();
    quiet.record(use ? (s == TeamTrial::kSamples ? 50.0 : 0.75) : 1.0);
  }
  EXPECT_TRUE(quiet.useTeam());
}

TEST(TeamTrial, AFirstTeamSubstepThatWaitedATimeSliceDoesNotDecide) {
  TeamTrial trial;
  // The team is faster, but its very first substep waited 300 times one thread's substep for its threads.
  bool first = true;
  for (int s = 0; s < 200; ++s) {
    const bool use = trial.useTeam();
    trial.record(use ? (first ? 300.0 : 0.75) : 1.0);
    first = first && !use;
  }
  EXPECT_TRUE(trial.useTeam());
}

TEST(TeamTrial, AStalledStartDoesNotPostponeTheNextProbe) {
  TeamTrial trial;
  // The first probe: the team's threads start late (100 substeps' time), then it runs as fast as one thread
  // (the cloth still falling, little to share): a loss, but one that cost nothing beyond the start.
  bool first = true;
  for (int s = 0; s < 2 * TeamTrial::kSamples + 8; ++s) {
    const bool use = trial.useTeam();
    trial.record(use ? (first ? 100.0 : 1.0) : 1.0);
    first = first && !use;
  }
  ASSERT_FALSE(trial.useTeam());
  // The cloth folds and the team pays: it is tried again at the shortest wait.
  runTrial(trial, 3 * TeamTrial::kMinInterval, 1.0, 0.75);
  EXPECT_TRUE(trial.useTeam());
}

TEST(TeamTrial, FollowsTheMachineWhenItChanges) {
  TeamTrial trial;
  runTrial(trial, 3000, 1.0, 12.0);  // busy: one thread
  ASSERT_FALSE(trial.useTeam());
  // Quiet again: the team is back at the next probe.
  const long long quiet = runTrial(trial, 10000, 1.0, 0.75);
  EXPECT_TRUE(trial.useTeam());
  EXPECT_GT(quiet, 10000 - 4000);
  // Busy again: noticed within two windows of kMinInterval substeps, not at the next scheduled probe.
  runTrial(trial, 2 * TeamTrial::kMinInterval + TeamTrial::kSamples + 2, 1.0, 3.0);
  EXPECT_FALSE(trial.useTeam());
}

TEST(TeamTrial, AMarginSmallerThanTheHysteresisDoesNotFlip) {
  TeamTrial trial;
  runTrial(trial, 1000, 1.0, 0.8);
  ASSERT_TRUE(trial.useTeam());
  // One thread now measures 2.5% faster than the team: not enough to switch back and forth on noise.
  runTrial(trial, 10000, 0.78, 0.8);
  EXPECT_TRUE(trial.useTeam());
}

TEST(TeamTrial, OneOutlierDoesNotDecide) {
  TeamTrial trial;
  // The team is faster, but one substep of its first probe is interrupted (a time slice lost): its slowest
  // substep is not counted.
  for (int s = 0; s < 200; ++s) {
    const bool use = trial.useTeam();
    trial.record(use ? (s == TeamTrial::kSamples + 5 ? 50.0 : 0.75) : 1.0);
  }
  EXPECT_TRUE(trial.useTeam());
}

TEST(TeamTrial, ACloseLossIsTriedAgainSoon) {
  TeamTrial trial;
  // The first probe finds the team 2% slower (a few noisy substeps; a loss all the same)...
  runTrial(trial, 2 * TeamTrial::kSamples + 8, 1.0, 1.02);
  ASSERT_FALSE(trial.useTeam());
  // ...and it costs 2% of a probe, so the next comes after the shortest wait, not after 50 probes' time.
  runTrial(trial, 3 * TeamTrial::kMinInterval, 1.0, 0.75);
  EXPECT_TRUE(trial.useTeam());
}

// Every 12th substep also rebuilds (irregular), at 3 times a regular one's work either way: the trial compares the
// regular ones, so each probe measures the team at what it takes on them.
TEST(TeamTrial, SubstepsWithAJobOfTheirOwnAreLeftOutOfTheComparison) {
  TeamTrial trial;
  std::vector<double> ratios;
  long long on_team = 0;
  for (long long s = 0; s < 3000; ++s) {
    const bool use = trial.useTeam(), regular = s % 12 != 5;
    on_team += use;
    const double work = regular ? 1.0 : 3.0;
    trial.record(work * (use ? 0.75 : 1.0), regular);
    if (ratios.empty() || trial.teamOverSolo() != ratios.back()) ratios.push_back(trial.teamOverSolo());
  }
  EXPECT_TRUE(trial.useTeam());
  EXPECT_GT(on_team, 3000 - 100);
  // Counting the rebuilds, a probe of 16 substeps (its slowest left out) against the mean of a longer run puts the
  // team at 0.74-0.88 of one thread's time, by where the rebuilds fall
  for (const double r : ratios) {
    if (!std::isnan(r)) {
      EXPECT_NEAR(r, 0.75, 1e-12);
    }
  }
  // Substeps that are all irregular count: the probes end and decide as before
  TeamTrial busy;
  for (long long s = 0; s < 1000; ++s) {
    const bool use = busy.useTeam();
    busy.record(use ? 0.75 : 1.0, false);
  }
  EXPECT_TRUE(busy.useTeam());
  EXPECT_NEAR(busy.teamOverSolo(), 0.75, 1e-12);
}

// The processors' idle time between two readings of /proc/stat, as the room for a team is judged.
TEST(TeamTrial, IdleProcessorsBetweenTwoReadings) {
  EXPECT_DOUBLE_EQ(idleProcessors({100, 1000}, {300, 1400}, 2, 4), 1.0) << "half of two processors' ticks idle";
  EXPECT_DOUBLE_EQ(idleProcessors({100, 1000}, {100, 1400}, 2, 4), 0.0);
  EXPECT_TRUE(std::isnan(idleProcessors({100, 1000}, {102, 1003}, 2, 4))) << "three ticks say little";
  EXPECT_TRUE(std::isnan(idleProcessors({100, 1000}, {90, 1400}, 2, 4))) << "not a later reading";
  EXPECT_TRUE(std::isnan(idleProcessors({100, 1000}, {900, 1400}, 2, 4))) << "more idle than in all";
}

// The tasks runnable now, as the room for a team is judged before the ticks say anything
TEST(TeamTrial, TheTasksRunnableNowFromProcLoadavg) {
  EXPECT_EQ(runnableTasks("1.51 1.39 1.38 1/109 29822"), 1);
  EXPECT_EQ(runnableTasks("0.00 0.01 0.05 12/1204 7\n"), 12);
  EXPECT_EQ(runnableTasks("1.51 1.39 1.38 0/109 29822"), -1) << "the caller is running";
  EXPECT_EQ(runnableTasks("1.51 1.39 1.38 3/2 29822"), -1);
  EXPECT_EQ(runnableTasks("1.51 1.39 1.38"), -1);
  EXPECT_EQ(runnableTasks(""), -1);
  // On two processors a team of two has room while the caller runs alone, not beside another task
  EXPECT_TRUE(roomAmongRunnable(1, 2, 2));
  EXPECT_FALSE(roomAmongRunnable(2, 2, 2));
  EXPECT_TRUE(roomAmongRunnable(2, 4, 3));
  EXPECT_FALSE(roomAmongRunnable(3, 4, 3));
}

TEST(TeamTrial, NoCoreForTheTeamNoProbe) {
  bool room = false;
  TeamTrial trial([&] { return room; });
  EXPECT_EQ(runTrial(trial, 5000, 1.0, 0.75), 0) << "the machine had no core for the team: never tried";
  room = true;
  runTrial(trial, 2 * TeamTrial::kMinInterval + TeamTrial::kSamples + 2, 1.0, 0.75);
  EXPECT_TRUE(trial.useTeam());
}

// Which cloths get a trial: from kTeamTrialMinPoints to kTeamMinPoints, with more than one thread; and
// whatever way each substep took, the bytes are one thread's.
TEST(TeamTrial, AMidSizedClothRunsOneAndKeepsItsBytes) {
  Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  ASSERT_GE(scene.cloth.num_width_points * scene.cloth.num_height_points, kTeamTrialMinPoints);
  CpuSolver<float> one(scene, CpuSolverOptions{.threads = 1});
  CpuSolver<float> trial(scene, CpuSolverOptions{.threads = 2});
  EXPECT_EQ(one.teamTrial(), nullptr);
  ASSERT_NE(trial.teamTrial(), nullptr);
  EXPECT_EQ(trial.teamThreads(), 2);
  EXPECT_EQ(CpuSolver<float>(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0}).teamTrial(), nullptr)
      << "a team from 0 points: always";
  for (int f = 0; f < 4; ++f) {
    one.stepFrame();
    trial.stepFrame();
  }
  EXPECT_TRUE(sameBytes(one.positions(), trial.positions()));
  EXPECT_TRUE(sameBytes(one.displacements(), trial.displacements()));
  scene.cloth.num_width_points = scene.cloth.num_height_points = 20;
  scene.cloth.pinned.clear();
  const CpuSolver<float> small(scene, CpuSolverOptions{.threads = 2});
  EXPECT_EQ(small.teamThreads(), 1) << "400 points: one thread";
  EXPECT_EQ(small.teamTrial(), nullptr);
}

}  // namespace
}  // namespace drape
