// `drape bench --roofline`: how close each CPU pass comes to this machine's limits. Per pass, the work a point
// costs (vector adds and multiplies, divisions and square roots, bytes to and from memory), counted from the
// float grid path's code (cpu/grid_kernels.inl, cpu/cpu_solver.cpp); the ceilings measured by small probes
// (cpu/machine_peak.hpp); and the pass's measured time against the least time those ceilings allow.
#pragma once

#include "app/bench.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace drape {

// Per point and call of a pass. Bytes are each array's traffic once per call (what a pass must move when its
// data is not already in cache); the self-collision list's rebuilds are not in it (their rate is reported).
struct PassWork {
  double addmul = 0;   // vector adds and multiplies
  double divsqrt = 0;  // divisions and square roots
  double bytes = 0;
};

// What the roofline needs of a CPU run (bench's benchOne calls it): the path it took and the self-collision
// lists' shape at the end of the run.
void recordCpuDetails(const Solver& solver, const Scene& scene, BenchRun& run);
nlohmann::json peaksJson(const std::vector<MachinePeak>& peaks);

// The work of `pass` in `run` (a CPU float run of the Verlet integrator), or nothing for a pass the model
// does not cover (the implicit sweeps, tethers, the mesh path).
std::optional<PassWork> passWork(const BenchRun& run, const std::string& pass);

// The markdown section: the probes, then per run and pass the work a point, the least time the ceilings
// allow (the binding one named), the measured time and their ratio, the share of the roofline reached.
std::string rooflineMarkdown(const BenchReport& report);

}  // namespace drape
