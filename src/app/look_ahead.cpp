#include "app/look_ahead.hpp"

#include "app/progress.hpp"
#include "app/solver_factory.hpp"

#include <unistd.h>

namespace drape {

SceneExtent lookAheadExtent(const Scene& scene, const Topology& topology, int frames, const std::string& label) {
  SceneExtent extent(scene, topology);
  SolverFactory factory;
  const std::unique_ptr<Solver> solver = factory.make(scene, "cpu");
  TerminalProgress progress(label + ": framing the run, frame", frames, ::isatty(STDERR_FILENO));
  lookAhead(extent, *solver, frames, [&](int frame, const std::vector<glm::dvec3>&) { progress.update(frame); });
  return extent;
}

}  // namespace drape
