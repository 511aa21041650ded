// `drape accuracy`: error against run time. Every configuration (solver x substeps x stretch passes)
// is compared with a double-precision CPU run at reference_factor times the scene's substeps, whose
// own convergence is measured against twice as many substeps.
#pragma once

#include "app/measure.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace drape {

// The latest sample time, s (--times), and the most frames a sample time may be at the scene's
// frames_per_sec: bounds that keep a typo from running for days (or overflowing the frame count).
inline constexpr double kMaxSampleTime = 600.0;
inline constexpr int kMaxSampleFrames = 1000000;

struct AccuracyOptions {
  std::string scene;  // scene file
  std::vector<int> steps = {5, 10, 20, 30, 60, 120};
  std::vector<std::string> solvers = {"cpu-xprev", "cpu", "cpu64", "gpu"};
  std::vector<int> stretch_passes = {1, 2, 4};
  std::vector<double> times = {0.5, 1.0, 2.0};  // s; rounded to whole frames
  int reference_factor = 16;                    // reference substeps = this x the scene's
  int jobs = 0;  // CPU runs side by side, each on its share of the cores (0: one per core); GPU runs one at a time
};

// One configuration's state at one sample time, against the reference with the same stretch passes.
struct ErrorSample {
  double t = 0;  // s, frame / frames_per_sec
  int frame = 0;
  double rms_error = 0;    // RMS position error / cloth size (diagonal)
  double max_error = 0;    // m, largest vertex error
  double max_strain = 0;   // of this configuration's state
  double penetration = 0;  // m, deepest point inside a collider (0 if none)
  double vs_double = -1;   // RMS distance / cloth size to cpu64 at the same substeps and passes; -1 if none
};

struct AccuracyRun {
  std::string solver;
  int steps_per_frame = 0;
  int stretch_passes = 0;
  std::string skipped;      // why it did not run
  std::string unstable;     // what happened, when it blew up
  int unstable_frame = -1;  // first frame the blow-up check failed
  double ms_per_sim_s = 0;  // wall ms per simulated second, stepping only
  std::vector<ErrorSample> samples;
};

// The reference (reference_factor x substeps) against its check (twice that), per stretch-pass count.
struct ReferenceCheck {
  int stretch_passes = 0;
  int steps_per_frame = 0, check_steps_per_frame = 0;
  std::string unstable;
  std::vector<ErrorSample> samples;  // error = reference vs check; strain and penetration of the reference
  double wall_s = 0;
};

struct AccuracyReport {
  std::string scene;
  std::string started_at;
  double wall_s = 0;
  MachineInfo machine;
  std::optional<GlInfo> gl;
  AccuracyOptions options;
  int jobs = 1;             // CPU runs side by side
  int threads_per_run = 0;  // each CPU run's solver threads
  std::vector<ReferenceCheck> references;
  std::vector<AccuracyRun> runs;
};

// `progress` gets one line per step, each finished run's line starting with "k/N, elapsed, about T left:".
// `finished` gets the report so far each time a run finishes (the references, then the runs finished,
// in the report's order), so that a caller can keep what is done if the sweep is stopped.
AccuracyReport runAccuracy(const AccuracyOptions& options, const std::function<void(const std::string&)>& progress = {},
                           const std::function<void(const AccuracyReport&)>& finished = {});

// The order of convergence of one solver at one stretch-pass count: the error falling as substeps^-order,
// fitted by least squares to log(error) against log(substeps) over its stable runs whose error (the largest
// over the sample times) is at least kResolvedFactor times the reference's own (reference against check):
// below that the reference cannot tell the error apart. Meaningful with the stretch limit off (passes 0),
// where nothing but the integrator sets the error.
struct ConvergenceOrder {
  double order = 0;  // -slope; NaN when fewer than 3 runs qualify
  int runs = 0;      // how many were fitted
  int smallest_steps = 0, largest_steps = 0;
};
inline constexpr double kResolvedFactor = 4.0;
ConvergenceOrder convergenceOrder(const AccuracyReport& report, const std::string& solver, int stretch_passes);

std::string accuracyCsv(const AccuracyReport& report);
std::string referenceCsv(const AccuracyReport& report);
std::string accuracyMarkdown(const AccuracyReport& report);

}  // namespace drape
