// A substep run by a team of threads gives one thread's bytes in every bundled scene, with every integrator,
// in float and double; the cloths that get a team trial (cpu/team_trial.hpp, its decisions in team_trial_test.cpp)
// keep their bytes and the team's shares of the work whichever way a substep runs.
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

// A trial's probe runs a few substeps on one thread between the team's: the team's shares of self-collision's search,
// finds and sums, which followed its times, are where it left them when it comes back (reset to even, they started
// over after each probe).
TEST(TeamBytesContact, TheTeamsSharesOutlastASubstepOnOneThread) {
  OneThreadAndTeam run;
  for (int f = 0; f < 45; ++f)
    run.stepFrame();
  const auto n = (long long)run.team.positions().size();
  const std::vector<long long> sums = run.team.pairShares(), find = run.team.findShares();
  const std::string said = describeThreads(run.team);
  ASSERT_EQ(sums.size(), 3u);
  ASSERT_NE(sums[1], n / 2) << "the shares have followed the times";
  // The same state again makes the next pass rebuild its lists, outside the team: the build and the pass on one thread
  const std::vector<glm::dvec3> x(run.one.positions().begin(), run.one.positions().end()),
      v(run.one.displacements().begin(), run.one.displacements().end());
  run.team.setState(x, v);
  run.team.selfCollide();
  EXPECT_EQ(run.team.pairShares(), sums);
  EXPECT_EQ(run.team.findShares(), find);
  EXPECT_EQ(describeThreads(run.team).substr(said.find("each thread's share")),
            said.substr(said.find("each thread's share")))
      << said;
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

// A team that records its waits (`simulate --waits`) files the two barriers that close each substep (in cpu_solver.cpp)
// once a substep on each thread, waits no longer than it ran, and computes the bytes it computes unrecorded.
TEST(TeamWaits, EachSubstepsClosingBarriersAreFiledOnceASubstep) {
  const Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/selfCollision.json");
  CpuSolver<float> recorded(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0, .record_waits = true});
  CpuSolver<float> plain(scene, CpuSolverOptions{.threads = 2, .team_min_points = 0});
  for (int f = 0; f < 3; ++f) {
    recorded.stepFrame();
    plain.stepFrame();
  }
  EXPECT_TRUE(sameBytes(recorded.positions(), plain.positions()));
  EXPECT_EQ(plain.waits(), nullptr);
  EXPECT_EQ(describeWaits(plain), "");
  const WaitLog* log = recorded.waits();
  ASSERT_NE(log, nullptr);
  ASSERT_EQ(recorded.teamSubsteps(), 90);
  int closing = 0;
  for (const WaitLog::Site& s : log->sites())
    closing += s.file == "cpu/cpu_solver.cpp" && s.count == std::vector<long long>{90, 90};
  EXPECT_EQ(closing, 2);
  for (const double seconds : log->totals()) {
    EXPECT_GT(seconds, 0);
    EXPECT_LT(seconds, recorded.teamSeconds());
  }
  const std::string said = describeWaits(recorded);
  EXPECT_NE(said.find("a team of 2 ran 90 substeps"), std::string::npos) << said;
  EXPECT_NE(said.find("cpu/cpu_solver.cpp:"), std::string::npos) << said;
  recorded.reset();
  EXPECT_TRUE(recorded.waits()->sites().empty()) << "reset() starts the log again";
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
