// What `drape bench`, `drape accuracy` and `drape stability` share: the solver factory
// (app/solver_factory.hpp), resampling a scene's cloth, the machine's description, order statistics of
// timings.
#pragma once

#include "app/solver_factory.hpp"
#include "core/scene.hpp"

#include <string>
#include <vector>

namespace drape {

// The scene with its cloth resampled to n x n points: width, height and density (kg/m^2, so the
// total mass) stay, pins keep their relative grid place (corners stay corners), and thickness is
// capped at 0.45 x spacing so that neighbours at rest are outside the self-collision range 2 x thickness,
// unless keep_thickness (a CS184 file refined as it is, with neighbours held at rest).
Scene resampleCloth(const Scene& scene, int n, bool keep_thickness = false);

struct MachineInfo {
  std::string hostname, cpu_model, kernel;
  int logical_cores = 0;
  long long memory_bytes = 0;
  std::string load_average;  // /proc/loadavg's 1, 5 and 15 minute figures when read: others' work on these cores
};
MachineInfo readMachineInfo();
std::string readLoadAverage();

// Order statistics of timing samples (linear interpolation between order statistics).
struct Spread {
  double median = 0, min = 0, max = 0, q1 = 0, q3 = 0;
  int samples = 0;
};
Spread summarize(std::vector<double> values);

// "2026-11-22T03:50:00Z"
std::string utcTimestamp();

}  // namespace drape
