// CpuSolver's state in and out: set, read back and checked, and copied back from the grid path's padded arrays
// where a substep left it there. Kept apart from cpu_solver.cpp for its size.
#include "cpu/cpu_solver.hpp"

#include "cpu/parallel.hpp"

#include <type_traits>

namespace drape {

template <class T>
void CpuSolver<T>::syncPositions() const {
  if (!positions_behind_) return;
  if constexpr (std::is_same_v<T, float>) {
    // Logically const: x_ and v_ as the last substep left them, copied from where it left them
    auto& self = const_cast<CpuSolver&>(*this);
    self.grid_->storePositions(self.x_, self.v_);
  }
  positions_behind_ = false;
}

template <class T>
void CpuSolver<T>::setState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v) {
  positionsMoved();
  pairs_.invalidate();
  for (std::size_t i = 0; i < x_.size(); ++i) {
    x_[i] = vec3(x[i]);
    v_[i] = form_ == VerletForm::Displacement ? vec3(v[i]) : vec3(x[i] - v[i]);
  }
}

// Solver::health's scan on the state as it is, without the double copies readPositions and
// readDisplacements make, and split between the threads on a large cloth (a frame's serial tail at 256^2:
// 3% of a two-thread run's samples): the parts merge to the one scan's answer.
template <class T>
Health CpuSolver<T>::health() {
  // Where the last substep left x and v in the grid path's arrays, their quick look there first (GridPath::healthy):
  // no copy back, and the springs a vector at a time. On the vec3s the look was a frame's serial tail, 1.2% of
  // selfCollision's samples on one thread, the team's other threads idle through it.
  if constexpr (std::is_same_v<T, float>)
    if (grid_ && positions_behind_ && form_ == VerletForm::Displacement && quick_health_.usable &&
        grid_->healthy(quick_health_.bound)) {
      Health h;
      h.substeps = substeps();
      return h;
    }
  syncPositions();
  if (form_ != VerletForm::Displacement) return Solver::health();
  const std::size_t n = x_.size(), springs = topo_.springs.size();
  const int parts = teamFor(threads_, (long long)(n + springs));
  std::vector<Health> part(static_cast<std::size_t>(parts));
#pragma omp parallel for num_threads(parts) schedule(static)
  for (int k = 0; k < parts; ++k) {
    const std::size_t p0 = n * k / parts, p1 = n * (k + 1) / parts, s0 = springs * k / parts,
                      s1 = springs * (k + 1) / parts;
    if constexpr (std::is_same_v<T, float>)
      if (quickHealthy(quick_health_, x_, v_, p0, p1, s0, s1)) continue;  // the scan would find nothing
    part[std::size_t(k)] = scanHealthPart(topo_, scene_.cloth, x_, v_, HealthLimits{}, p0, p1, s0, s1);
  }
  Health h;
  for (const Health& p : part)
    h.merge(p);
  h.substeps = substeps();
  return h;
}

template <class T>
std::vector<glm::dvec3> CpuSolver<T>::readPositions() {
  syncPositions();
  return std::vector<glm::dvec3>(x_.begin(), x_.end());
}

template <class T>
std::vector<glm::dvec3> CpuSolver<T>::readDisplacements() {
  syncPositions();
  std::vector<glm::dvec3> out(x_.size());
  for (std::size_t i = 0; i < x_.size(); ++i)
    out[i] = form_ == VerletForm::Displacement ? glm::dvec3(v_[i]) : glm::dvec3(x_[i]) - glm::dvec3(v_[i]);
  return out;
}

template void CpuSolver<float>::syncPositions() const;
template void CpuSolver<double>::syncPositions() const;
template void CpuSolver<float>::setState(const std::vector<glm::dvec3>&, const std::vector<glm::dvec3>&);
template void CpuSolver<double>::setState(const std::vector<glm::dvec3>&, const std::vector<glm::dvec3>&);
template Health CpuSolver<float>::health();
template Health CpuSolver<double>::health();
template std::vector<glm::dvec3> CpuSolver<float>::readPositions();
template std::vector<glm::dvec3> CpuSolver<double>::readPositions();
template std::vector<glm::dvec3> CpuSolver<float>::readDisplacements();
template std::vector<glm::dvec3> CpuSolver<double>::readDisplacements();

}  // namespace drape
