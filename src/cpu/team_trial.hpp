// Whether a substep of a mid-sized cloth runs on a team of threads or on one, decided by timing both.
//
// Below kTeamMinPoints a substep's loops are short (a 50x50 cloth's take 5-50 us each) and a team pays only
// when every thread has a core of its own: measured on the 2-core development machine, a team of two ran
// a 50x50 substep 1.3x faster when the machine was quiet, and up to a thousand times slower when other
// jobs held both cores (each of a substep's barriers waits for a descheduled thread's next time slice;
// docs/results/cpu_speed.md). Neither choice is right on a shared machine, so the solver measures: it runs
// one way, now and then times a few substeps the other way, and keeps the faster. A probe costs at most
// kProbeShare of the run: the more the other way lost by, the longer until it is tried again, and a probe
// that has already lost stops at once. The team is not tried at all while the machine has no core for its
// other threads (the caller's `room`: the processors' idle time, or the load average and the tasks runnable now). The
// bytes are the same either way: what is decided here is only how long they take.
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <string>
#include <utility>

namespace drape {

// The processors' time as /proc/stat counts it, all of them together, in clock ticks: idle (idle and
// iowait) and in all.
struct ProcessorTicks {
  long long idle = 0, total = 0;
};

// How many processors were idle on average between two readings, or NaN where fewer than min_ticks passed
// (a tick is a hundredth of a second of one processor: a shorter interval says little) or the readings do
// not follow each other.
inline double idleProcessors(ProcessorTicks before, ProcessorTicks after, int processors, long long min_ticks) {
  const long long total = after.total - before.total, idle = after.idle - before.idle;
  if (total <= 0 || total < min_ticks || idle < 0 || idle > total) return std::numeric_limits<double>::quiet_NaN();
  return double(processors) * double(idle) / double(total);
}

// The tasks runnable now, the caller among them, from the text of /proc/loadavg (its fourth field, "runnable/all"),
// or -1 where the text is not that.
int runnableTasks(const std::string& loadavg);

// Whether a team of `team` threads has a processor for each thread when `runnable` tasks are runnable now, the caller
// among them (the team's first thread), on `processors` processors.
inline bool roomAmongRunnable(int runnable, int processors, int team) {
  return runnable - 1 + team <= processors;
}

// The `room` a trial of a team of `team` threads asks on this machine (cpu/team_trial.cpp): whether the
// processors' idle time since the last ask (or since this call) leaves a core for each of its other threads;
// until a few ticks have passed, whether the 1-minute load average or the tasks runnable now (roomAmongRunnable) do.
std::function<bool()> machineRoom(int team);

// The processor time a team of `team` threads has missed since this call: `team` times the wall-clock time less the
// process's processor time (CLOCK_PROCESS_CPUTIME_ID), in seconds. A team's threads spin while they wait, so a quiet
// machine leaves it near 0 however the work grows; another job that takes a core adds to it (cpu/team_trial.cpp).
// What tells a team slowed by another job from one slowed by its work: a count of preemptions (getrusage's involuntary
// switches) could not, a quiet two-thread run of CS184's selfCollision having 10-130 of them. The process's other
// threads (a renderer's) count as the team's: there a slowdown is more often taken for the work.
std::function<double()> missedProcessorTime(int team);

// Moves each thread of an OpenMP team of `team` to a processor of its own once, then lets the scheduler place it
// again (cpu/team_trial.cpp). A new thread starts on the core of the thread that made it, and while that one
// spins at the region's barrier the scheduler moves the newcomer only at its next balance: the first team substep
// of pinned2 took 3.3-20 ms in 13 of 20 runs (160-360 us otherwise; 69-97 us in 20 of 20 after the spread). Returns
// whether every thread moved (false where there are fewer processors than threads, or affinity cannot be set).
bool spreadTeam(int team);

class TeamTrial {
 public:
  static constexpr int kSamples = 16;  // substeps a probe counts (it runs one more: its slowest is not counted)
  static constexpr long long kMinInterval = 64;  // substeps between probes, after a switch
  static constexpr long long kMaxInterval = 1 << 20;
  static constexpr double kProbeShare = 0.02;  // of the run's time, what probing may cost at the most
  // The other way must take at most this fraction of the current way's time to be taken: noise of a few
  // percent does not flip the choice back and forth.
  static constexpr double kHysteresis = 0.95;
  // One thread must take at most this fraction of a team's time to replace it. A team back from a probe of one
  // thread takes about a hundred substeps to regain its speed (CS184's selfCollision: 9% slower over the first 20,
  // 4% over the next 40), and on a shared machine one thread's passes slowed by half for 100-250 substeps at a time
  // (the other's not), which made a team as slow as one thread: one thread won such probes by a few percent and,
  // each later probe of the team a close loss, kept runs for up to 2,000 substeps after the team was fast again. A
  // team that has gone that much slower (a core taken) still loses at once.
  static constexpr double kLeaveTeam = 0.85;
  // A team measured at this fraction of one thread's time or less is probed against one thread again only once it
  // has slowed by kSlowdown (record): until then it takes under kDecisive x kSlowdown of one thread's time, too little
  // for one thread to replace it (kLeaveTeam).
  static constexpr double kDecisive = 0.78;
  // A team whose last kMinInterval substeps took this many times what it measured, and which missed more than
  // kMissedShare of a processor's time over them, is probed against one thread at once.
  static constexpr double kSlowdown = 1.5;
  static constexpr double kMissedShare = 0.1;
  static_assert(kDecisive * kSlowdown < 1 / kLeaveTeam);
  // A probe whose first substeps (kClearAfter of them, the slowest left out) took this many times the current way's
  // mean has lost: the rest of it could not bring it under kHysteresis or kLeaveTeam. A one-thread probe of a team at
  // 0.6 of its time ran 11 substeps before the sum said so.
  static constexpr double kClearLoss = 1.25;
  static constexpr int kClearAfter = 4;
  // What a probe of one thread costs a team beyond its own substeps, in the team's substeps: the caches' lines
  // moved to one core and back, and the team's hundred substeps of settling after it (9% slower over the first 20
  // on CS184's selfCollision, 4-5% over the next 60). Reckoned into the wait for the next probe.
  static constexpr double kLeaveCost = 6;
  // One substep of a probe this many times the current way's mean ends it, lost: a team whose barriers each
  // wait for a time slice (both cores busy) takes a thousand times one thread's substep, 0.1 s at 50 x 50,
  // and a second such substep would double the probe's cost. An interrupted substep on a quiet machine (a
  // few milliseconds) stays under it.
  static constexpr double kAbsurd = 200;

  // `room`: whether the machine has a core for each of the team's other threads now (asked before a probe
  // of the team, not every substep).
  // `missed`: the processor time the team has missed so far, in seconds (missedProcessorTime), or none where a
  // slowdown is to be taken for a lost core whatever the cause.
  explicit TeamTrial(
      std::function<bool()> room = [] { return true; }, std::function<double()> missed = nullptr)
      : room_(std::move(room)), missed_(std::move(missed)) {}

  bool useTeam() const { return probing_ ? !team_ : team_; }

  // The substep just run (the way useTeam() said) took `seconds` of wall-clock time. regular: it did only the work
  // every substep does. One that also did a job of its own now and then (a rebuild of the self-collision lists: one
  // substep in 12 on CS184's selfCollision, 2-4 times a substep's work) is left out of the means either way runs, so
  // that both compare the same work: a probe of 16 substeps holds one such job or two or none, while the mean it is
  // measured against holds them at their rate, and on that file the probes put the team at 0.38-0.91 of one thread's
  // time where it takes about 0.7, and in 1 run of 30 kept one thread for 220 substeps of 2700. Where irregular ones
  // are most of those seen since the last probe ended (kSamples at least), they count (a probe of them would not end).
  void record(double seconds, bool regular = true) {
    ++tally_.seen;
    tally_.irregular += !regular;
    const bool counted = regular || (tally_.seen >= kSamples && 2 * tally_.irregular > tally_.seen);
    if (!probing_) {
      // Means, not medians: a team's time on a busy machine is mostly short substeps and a few that wait a
      // whole time slice, and those few are the cost.
      if (!first_ && counted) {  // the very first substep builds what the run keeps (lists, caches)
        // The mean of this way's substeps since the last probe, the last kMinInterval weighing most: the machine's
        // state changes (a team took one thread's time for hundreds of substeps, then 0.6 of it again), and a probe
        // after such a stretch measured one thread against it, won, and kept it for 146 substeps.
        mean_ += (seconds - mean_) / double(std::min(++count_, kMinInterval));
        if (window_count_ == 0 && missed_) window_missed_ = missed_();
        window_sum_ += seconds;
        if (++window_count_ == kMinInterval) {
          // A team that has become much slower than it measured because another job took a core (it missed a
          // tenth of a processor's time or more) tries one thread now rather than at its next probe; one thread is
          // never that costly to try. A team slowed by its work alone (a cloth that folds: CS184's selfCollision's team
          // takes 18 us a substep at first and 40-60 late in the run) ran as fast as it could, and one thread would
          // have slowed as much: its time becomes the measure. Either way the window's mean is the team's time now,
          // which a probe measures one thread against.
          if (team_ && window_sum_ / double(kMinInterval) > kSlowdown * typical_) {
            if (!missed_ || missed_() - window_missed_ > kMissedShare * window_sum_)
              countdown_ = 1;
            else
              typical_ = window_sum_ / double(kMinInterval);
            mean_ = window_sum_ / double(kMinInterval);
            count_ = kMinInterval;
          }
          window_sum_ = 0;
          window_count_ = 0;
        }
      }
      first_ = false;
      if (--countdown_ > 0) return;
      // (A window that called for a probe left its mean over kSlowdown x typical_: it is probed.)
      if (team_ && team_over_solo_ <= kDecisive && count_ > 0 && mean_ <= kSlowdown * typical_) {
        // A team that beat one thread by kDecisive and has not slowed since: one thread could replace it only by
        // taking under kLeaveTeam of its time, which its work alone does not make it do (CS184's selfCollision: 0.52
        // to 0.78 over the run, and each probe cost the team its settling). Not probed, and the interval doubles as
        // for a lost probe. Another job taking a core slows the team by far more: the window's check probes it at
        // once.
        interval_ = std::min(kMaxInterval, 2 * interval_);
        countdown_ = interval_;
        return;
      }
      if (team_ || room_()) {
        startProbe();
        refused_ = 0;
        return;
      }
      // No core for a team now: run alone and ask again, soon at first (the machine is often busy only for a
      // moment: run after another program, CS184's selfCollision was refused at substep 16 in 6 runs of 30 and had
      // its team at 80 or 144), then at the probes' interval.
      countdown_ = std::min(interval_, (long long)kSamples << std::min(refused_++, 16));
      return;
    }
    const double current = count_ > 0 ? mean_ : seconds;
    if (!counted && seconds <= kAbsurd * current) return;  // an absurd one counts: the machine stalled
    probe_sum_ += seconds;
    probe_max_ = std::max(probe_max_, seconds);
    ++probe_runs_;
    // The probe's time less its slowest substep (the first, where a team's threads wake, or one interrupted)
    // is what decides; once it exceeds what kSamples substeps may take to win, the other way has lost,
    // however the rest would go.
    const double needed = team_ ? kLeaveTeam : kHysteresis;  // the other way's time over this way's, to win
    const double limit = needed * current * double(kSamples);
    // The team's first substep of the run also starts its threads, which the scheduler may leave on one
    // core for a time slice before it spreads them: that one alone does not end the probe.
    const bool starting = !team_ && !team_tried_ && probe_runs_ == 1;
    const bool clear =
        probe_runs_ > kClearAfter && probe_sum_ - probe_max_ > kClearLoss * current * double(probe_runs_ - 1);
    const bool lost = clear || probe_sum_ - probe_max_ > limit || (seconds > kAbsurd * current && !starting);
    if (!lost && probe_runs_ < kSamples + 1) return;
    team_tried_ = team_tried_ || !team_;
    // (A probe stopped at its first substep has only that one to say how long the other way takes.)
    const double other = probe_runs_ > 1 ? (probe_sum_ - probe_max_) / double(probe_runs_ - 1) : probe_sum_;
    const double ratio = other / current;  // the other way's time over this way's
    team_over_solo_ = team_ ? 1 / ratio : ratio;
    probing_ = false;
    if (!lost && ratio <= needed) {
      team_ = !team_;
      typical_ = other;
      interval_ = kMinInterval;
    } else {
      typical_ = current;
      // Lost: try again when this probe's cost, the time it took beyond what this way would have, is
      // kProbeShare of the time run in between. The cost is reckoned as the decision was, without the slowest
      // substep (a team's first one may wait a time slice for its threads to start, once a run). A close loss
      // costs little and is soon tried again (the two ways' means are noisy over a few substeps); a team
      // that waited for time slices, seldom.
      // A clear loss, stopped early, is reckoned at the length the sum would have run to: stopping early saves the
      // probe's substeps, not the switches to the other way and back, which a probe as often would add.
      const double runs = clear ? std::max(double(probe_runs_), limit / other + 1) : double(probe_runs_);
      const double cost =
          (std::max(other - current, 0.0) * runs + (team_ ? kLeaveCost * current : 0.0)) / (kProbeShare * current);
      interval_ = (long long)std::min(double(kMaxInterval), std::max(2.0 * double(interval_), cost));
    }
    countdown_ = interval_;
    mean_ = window_sum_ = 0;
    count_ = window_count_ = 0;
    tally_ = {};
  }

  // The team's time over one thread's, at the last probe (NaN before the first).
  double teamOverSolo() const { return team_over_solo_; }

 private:
  void startProbe() {
    probing_ = true;
    probe_sum_ = probe_max_ = 0;
    probe_runs_ = 0;
  }

  std::function<bool()> room_;
  std::function<double()> missed_;
  double window_missed_ = 0;  // missed_() at the window's start
  bool team_ = false;         // the way substeps run between probes: one thread until the team has measured faster
  bool probing_ = false;
  bool team_tried_ = false;  // whether a probe of the team has finished
  bool first_ = true;
  long long interval_ = kMinInterval;
  long long countdown_ = kSamples;  // the first probe: as soon as one thread has a mean
  int refused_ = 0;                 // asks for room refused in a row
  double mean_ = 0;                 // this way's time a substep since the last probe (over count_ substeps; see record)
  long long count_ = 0;
  double typical_ = 0;     // this way's time a substep when it was last measured against the other
  double window_sum_ = 0;  // over the last window_count_ substeps (up to kMinInterval)
  long long window_count_ = 0;
  double probe_sum_ = 0, probe_max_ = 0;
  struct Tally {  // substeps recorded since the last probe ended, and how many of them were not regular
    long long seen = 0, irregular = 0;
  };
  Tally tally_;
  int probe_runs_ = 0;
  // The last probe's team time over one thread's (NaN before one: never under kDecisive)
  double team_over_solo_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace drape
