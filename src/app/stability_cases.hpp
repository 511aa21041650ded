// `drape stability`: stiff and extreme cases, each run at several substep counts, with and without the
// stability guard (core/stability.hpp), on the CPU float solver (the GPU's arithmetic).
#pragma once

#include "core/scene.hpp"

#include <functional>
#include <string>
#include <vector>

namespace drape {

// How a case starts, beyond the scene's flat cloth at rest.
enum class StartState {
  Rest,      // the scene's initial positions, zero velocity
  Jittered,  // every free point moved by up to jitter x spacing on each axis (seeded), zero velocity
  Crumpled,  // the cloth squeezed to crumple x its size in the plane and folded in a seeded wave
  Moving     // the scene's positions, every free point moving at start_velocity
};

struct StabilityCase {
  std::string name;
  std::string description;
  Scene scene;
  int frames = 180;
  StartState start = StartState::Rest;
  double jitter = 0.3;             // spacings (Jittered)
  double crumple = 0.3;            // fraction of the size kept (Crumpled)
  glm::dvec3 start_velocity{0.0};  // m/s (Moving)
  bool sweeps_ks = false;          // one of the ks cases: counted in the largest-stable-ks summary
  bool implicit_only = false;      // beyond what Verlet can run in reasonable time (ks 1e8, 1e9): XPBD and VBD only
};

// Every case of the issue: ks 1e2..1e7 (and 1e8, 1e9 for XPBD only), density 1..1e4, damping 0 and 100 %, a heavy cloth
// on two pins, a jittered and a crumpled start, a sphere struck at 20 m/s, a 10,000-frame soak.
std::vector<StabilityCase> stabilityCases();

// A run keeps its shape when it is stable and no spring ever stretched more than this (20%): "stable" alone
// only says that it did not blow up, which a cloth at 10 times its size passes.
inline constexpr double kShapeStrain = 0.2;

struct StabilityResult {
  std::string case_name;
  Integrator integrator = Integrator::Verlet;
  int steps_asked = 0;          // the substep setting of the sweep
  int steps_per_frame = 0;      // what ran: steps_asked, or the guard's count when guarded
  bool guarded = false;         // steps raised to autoSubsteps by the guard
  double stability_limit = 0;   // the guard's limit for the damping that ran
  double stability_number = 0;  // dt sqrt(k_sum/m) at these steps
  bool inside_bound = true;
  bool stable = true;
  int first_bad_frame = -1;
  std::string what;  // what broke, when unstable
  int frames_run = 0;
  double max_strain = 0;                    // over every frame run
  double end_strain = 0;                    // at the last frame run: what a cloth hangs at, not a passing peak
  double ke_max = 0, ke_end = 0;            // J
  double energy_start = 0, energy_end = 0;  // J: kinetic + gravitational + spring
  double energy_half = 0;                   // J: at half the frames, to tell a settled cloth's drift from its fall
  double energy_scale = 0;                  // J: what energy changes are relative to
  double wall_s = 0;
};

// Stable, and no spring stretched past kShapeStrain in any frame.
inline bool keepsShape(const StabilityResult& r) {
  return r.stable && r.max_strain <= kShapeStrain;
}

// Positions the case starts from (also the blow-up check's "start"), and displacements per substep.
void startState(const StabilityCase& c, std::vector<glm::dvec3>& x, std::vector<glm::dvec3>& v);

// threads: the CPU solver's threads (0 = every core); the result does not depend on it. The case's scene
// says which integrator runs; the guard applies to Verlet only.
StabilityResult runStabilityCase(const StabilityCase& c, int steps_per_frame, bool guard, int threads = 0);

struct StabilityReport {
  std::vector<int> steps;
  std::vector<int> implicit_steps;   // substep counts the implicit integrators ran at (no guard); empty: none ran
  std::vector<Integrator> implicit;  // which ran at those counts: XPBD, VBD, or both
  int jobs = 1;                      // runs side by side
  int threads_per_run = 0;           // each run's CPU solver threads
  std::vector<StabilityResult> results;
  double wall_s = 0;
};

// The result for a case at a substep setting, with or without the guard; null if it was not run (the
// guard only runs where it raises the count).
const StabilityResult* findResult(const StabilityReport& report, const std::string& case_name, int steps_asked,
                                  bool guarded, Integrator integrator = Integrator::Verlet);

// Runs every case at each substep count, and again with the guard wherever it raises the count; `jobs`
// runs side by side (0 = one per core, src/app/jobs.hpp), each on its share of the cores. Progress
// lines come in the order runs finish; the report keeps the order above.
// With implicit_steps, every case also runs with each integrator of `implicit` at each of those counts,
// without the guard.
StabilityReport runStability(const std::vector<StabilityCase>& cases, const std::vector<int>& steps,
                             const std::function<void(const std::string&)>& progress = {}, int jobs = 0,
                             const std::vector<int>& implicit_steps = {},
                             const std::vector<Integrator>& implicit = {Integrator::Xpbd});

std::string stabilityCsv(const StabilityReport& report);
std::string stabilityMarkdown(const StabilityReport& report, const std::vector<StabilityCase>& cases);

}  // namespace drape
