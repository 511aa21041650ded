#include "gpu/health.hpp"

#include "gpu/gpu_solver.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace drape {

std::string checkHealth(Solver& solver, double sane_bound) {
  if (auto* gpu = dynamic_cast<GpuSolver*>(&solver)) {
    const GpuHealth h = gpu->readHealth();
    if (h.ok()) return {};
    return (h.non_finite ? "non-finite position or displacement" : "a point left the sane bound") +
           std::string(" at point ") + std::to_string(h.first_point);
  }
  const std::vector<glm::dvec3> x = solver.readPositions();
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(x[i][a])) return "non-finite position at point " + std::to_string(i);
      if (std::abs(x[i][a]) > sane_bound) {
        char text[160];
        std::snprintf(text, sizeof text, "point %zu is beyond the sane bound of %g m (%.3g m)", i, sane_bound, x[i][a]);
        return text;
      }
    }
  }
  return {};
}

}  // namespace drape
