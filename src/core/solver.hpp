// What every solver (CPU float, CPU double, GPU) offers the commands: step, read back, describe passes,
// the blow-up check, waiting for the device and the device memory held.
#pragma once

#include "core/health.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <memory>
#include <string>
#include <vector>

namespace drape {

// Time spent in one named pass, accumulated since the last resetTimings().
struct PassTiming {
  std::string name;
  double ms = 0.0;      // total milliseconds (GPU: timer queries where they work, else wall clock)
  long long calls = 0;  // dispatches (GPU) or invocations (CPU)
};

class Solver {
 public:
  virtual ~Solver() = default;

  virtual std::string name() const = 0;  // "cpu", "cpu64", "gpu"
  virtual const Scene& scene() const = 0;
  virtual const Topology& topology() const = 0;

  virtual void step() = 0;  // one substep: the passes of docs/design.md section 2, in order
  // One frame: steps_per_frame substeps, then what runs once per frame. A solver may run the substeps
  // together (the GPU's one-dispatch path), with the same result as step() that often.
  virtual void stepFrame() {
    for (int s = 0; s < scene().sim.steps_per_frame; ++s)
      step();
    endFrame();
  }
  virtual void reset() = 0;  // back to the initial positions, time 0

  // Live parameter change (ks, damping, density, spring types, gravity, wind, ...). The grid size,
  // orientation and pins cannot change this way (reset with a new scene instead).
  virtual void setParams(const ClothSpec& cloth, const SimParams& sim) = 0;

  // Explicit, named read-back: never called per frame by the viewer.
  virtual std::vector<glm::dvec3> readPositions() = 0;
  virtual std::vector<glm::dvec3> readDisplacements() = 0;  // v = x - x_prev

  virtual long long substeps() const = 0;  // substeps taken since reset
  double time() const { return double(substeps()) * scene().sim.dt(); }

  // The blow-up check (core/health.hpp) on the state after the last pass stepped. The GPU answers from
  // flags its check kernel raised (a few bytes read back, which waits for the GPU); its flags stay
  // raised until reset().
  virtual Health health() {
    Health h = scanHealth(topology(), scene().cloth, readPositions(), readDisplacements());
    h.substeps = substeps();
    return h;
  }
  // The same check without making the CPU wait for the device, for loops that run every frame: the
  // newest answer the device has finished, which on the GPU is that of the frame before the last
  // stepFrame() (or of the last, when the device is already done with it), so one frame stays in
  // flight. Health::substeps says which state was checked. The CPU solvers answer for the current state.
  virtual Health recentHealth() { return health(); }
  // Blocks until every pass given so far has run: stop a clock after this. Nothing to wait for on the CPU.
  virtual void finish() {}
  // Bytes of device (GPU) memory the solver allocated; -1 for a solver whose state is in host memory.
  virtual long long deviceMemoryBytes() const { return -1; }

  virtual std::vector<std::string> passes() const = 0;  // passes dispatched per substep, in order
  // Passes dispatched once per frame, after the last substep's (stepFrame()).
  virtual std::vector<std::string> framePasses() const { return {}; }
  virtual int dispatchesPerFrame() const { return 0; }
  // Dispatches per substep: passes().size() where each pass is a dispatch of its own, less where one
  // dispatch runs several substeps (1 / steps_per_frame for the GPU's one-dispatch path); 0 on the CPU.
  virtual double dispatchesPerSubstep() const { return 0; }
  virtual int threads() const { return 0; }  // CPU threads the solver's loops may use; 0 for the GPU
  // Device memory traffic of one substep per cloth point, in bytes, as a model of what its passes read and
  // write (GpuSolver says how); 0 where no model exists (the CPU solvers).
  virtual double bytesPerPointPerSubstep() const { return 0; }
  virtual std::vector<PassTiming> timings() const { return {}; }
  virtual void resetTimings() {}

 protected:
  virtual void endFrame() {}  // what a solver runs once per frame, after stepFrame()'s last substep
};

}  // namespace drape
