// The team trial (cpu/team_trial.hpp), which decides whether a substep of a cloth below kTeamMinPoints runs on a
// team or on one thread, as a sequence of substep times: it picks the faster way by its measurements, probes the
// other again at intervals set by what probing costs, and follows the machine when it changes. The solver's side of
// it (the cloths that get one, their bytes) is in team_test.cpp.
#include "cpu/team_trial.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace drape {
namespace {

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

// A team whose substeps took 1.5 times what it measured is probed against one thread at once where it missed a tenth
// of a processor's time or more over them (another job took a core), and not where it missed less: a cloth that folds
// gives the team more work, and one thread as much more.
TEST(TeamTrial, ASlowdownWithoutMissedTimeIsTheWork) {
  double little = 0, lost = 0;
  // A window of kMinInterval substeps at 1.5 below is 96 seconds: each ask sees 5 more missed (under a tenth), or 100
  TeamTrial undisturbed([] { return true; }, [&] { return little += 5.0; });
  TeamTrial deprived([] { return true; }, [&] { return lost += 100.0; });
  // A team at 0.75 of one thread's time is decisive (kDecisive): no probe of one thread after the first
  for (TeamTrial* trial : {&undisturbed, &deprived})
    ASSERT_EQ(runTrial(*trial, 1600, 1.0, 0.75), 1600 - TeamTrial::kSamples);
  // The work doubles: two windows of kMinInterval substeps on the team at twice its time.
  const long long n = 2 * TeamTrial::kMinInterval + 2;
  EXPECT_EQ(runTrial(undisturbed, n, 2.0, 1.5), n) << "no probe: the team ran as fast as it could";
  EXPECT_EQ(runTrial(deprived, n, 2.0, 1.5), n - (TeamTrial::kClearAfter + 1)) << "a probe, lost";
  EXPECT_TRUE(undisturbed.useTeam());
  EXPECT_TRUE(deprived.useTeam());
}

// The processor time a team misses: all of it while the process sleeps, each thread's share of the wall-clock time.
TEST(TeamTrial, MissedProcessorTimeCountsWhatTheThreadsDidNotRun) {
  const auto one = missedProcessorTime(1), two = missedProcessorTime(2);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  const double missed_one = one(), missed_two = two();
  EXPECT_GE(missed_one, 0.025);
  EXPECT_LT(missed_one, 5.0);
  EXPECT_GE(missed_two, 2 * 0.025);
  EXPECT_GT(missed_two, missed_one);
}

// A team at kDecisive of one thread's time or less is not probed against one thread again until it slows by
// kSlowdown (each probe cost CS184's selfCollision's team its settling, and one thread never won one on a quiet
// machine); a team that won by less is probed as before.
TEST(TeamTrial, ADecisiveTeamIsProbedOnlyOnceItSlows) {
  TeamTrial decisive, close;
  const long long n = 3000;
  EXPECT_EQ(runTrial(decisive, n, 1.0, 0.75), n - TeamTrial::kSamples);
  // At 0.81 one thread takes 1.23 of the team's time, under kClearLoss: each of three probes runs until its sum less
  // its slowest passes kLeaveTeam x kSamples x 0.81 = 11.0 (13 substeps)
  EXPECT_EQ(runTrial(close, 1600, 1.0, 0.81), 1600 - TeamTrial::kSamples - 3 * 13);
  // Twice as slow (a core taken): the window's check probes it at once, and one thread wins
  runTrial(decisive, 2 * TeamTrial::kMinInterval + TeamTrial::kSamples + 2, 1.0, 2.0);
  EXPECT_FALSE(decisive.useTeam());
}

// A probe that has clearly lost stops after kClearAfter substeps and its slowest (a team at 0.6 of one thread's time:
// one thread's probe ran 11 substeps before its sum said so), and the next probe comes as late as if it had run on.
TEST(TeamTrial, AClearLossStopsEarly) {
  TeamTrial trial;
  long long solo = 0, probes = 0;
  for (long long s = 0; s < 3000; ++s) {
    const bool use = trial.useTeam();
    solo += !use;
    trial.record(use ? 0.6 : 1.0);
    probes += use && !trial.useTeam();
  }
  EXPECT_TRUE(trial.useTeam());
  EXPECT_EQ(solo, TeamTrial::kSamples + probes * (TeamTrial::kClearAfter + 1))
      << "one thread's first substeps, then each probe of one thread";
  EXPECT_LE(probes, 4) << "as many probes as when each ran until its sum said so";
  // A loss by less is not clear: it runs until its sum passes kLeaveTeam x kSamples x 0.9 = 12.2 (13 substeps) and
  // the slowest, 14.
  TeamTrial close;
  runTrial(close, 3 * TeamTrial::kSamples, 1.0, 0.9);
  ASSERT_TRUE(close.useTeam());
  EXPECT_EQ(TeamTrial::kMinInterval - runTrial(close, TeamTrial::kMinInterval, 1.0, 0.9), 14);
}

// A team that one thread beats by less than kLeaveTeam stays (a core slowed for a while, a team still warming up); one
// that one thread beats by more is left.
TEST(TeamTrial, OneThreadReplacesATeamOnlyByAMargin) {
  TeamTrial trial;
  runTrial(trial, 1000, 1.0, 0.75);
  ASSERT_TRUE(trial.useTeam());
  const long long n = 3000;
  EXPECT_GT(runTrial(trial, n, 1.0, 1.1), n - 100) << "one thread at 0.91 of the team's time: the team stays";
  EXPECT_TRUE(trial.useTeam());
  EXPECT_LT(runTrial(trial, 4 * n, 1.0, 1.25), 4 * n) << "at 0.8: one thread from the next probe on";
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

// A machine busy for a moment (another program just ended) refuses the first ask: the next comes kSamples substeps
// later, not at the probes' interval.
TEST(TeamTrial, AMomentsRefusalIsAskedAgainSoon) {
  int asks = 0;
  TeamTrial trial([&] { return ++asks > 1; });
  const long long on_team = runTrial(trial, 4 * TeamTrial::kSamples, 1.0, 0.75);
  EXPECT_EQ(asks, 2);
  EXPECT_TRUE(trial.useTeam());
  EXPECT_EQ(on_team, 2 * TeamTrial::kSamples) << "its probe from substep 2 kSamples on, won";
  // Refused again and again: asked after kSamples substeps, then 2 and 4 kSamples, then every kMinInterval
  int refusals = 0;
  TeamTrial busy([&] { return ++refusals < 0; });
  EXPECT_EQ(runTrial(busy, 10 * TeamTrial::kMinInterval, 1.0, 0.75), 0);
  EXPECT_EQ(refusals, 3 + (10 * TeamTrial::kMinInterval - 4 * TeamTrial::kSamples) / TeamTrial::kMinInterval);
}

}  // namespace
}  // namespace drape
