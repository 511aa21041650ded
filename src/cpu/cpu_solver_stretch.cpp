// CpuSolver's stretch limit (limitStretch): Provot's correction by colours (Gauss-Seidel, the grid kernels where
// they run) or averaged per point (Jacobi); kept apart from cpu_solver.cpp for its size.
#include "cpu/cpu_solver.hpp"
#include "cpu/cpu_solver_sweep.hpp"
#include "cpu/parallel.hpp"

#include <type_traits>

namespace drape {

template <class T>
void CpuSolver<T>::limitStretch(bool wait) {
  positionsMoved();
  if (scene_.sim.stretch_scheme == StretchScheme::GaussSeidel)
    limitStretchColoured(wait);
  else
    limitStretchJacobi();
}

// Provot (1995) as CS184 applies it, one spring after another, each moving its ends at once, but in
// colour order: the springs of a colour share no point, so they run in parallel and the result does not
// depend on the thread count. Holds the limit as tightly as CS184's sequential pass (the averaged
// Jacobi pass lets pinned2 reach 17% strain where this holds about 12.5%).
template <class T>
void CpuSolver<T>::limitStretchColoured(bool wait) {
  const T limit = T(scene_.sim.stretch_limit);
  const bool displacement = form_ == VerletForm::Displacement;
  if constexpr (std::is_same_v<T, float>)
    if (grid_) {
      const ClothSpec& c = scene_.cloth;
      const bool enabled[kSpringTypeCount] = {c.enable_structural, c.enable_shearing, c.enable_bending};
      // Inside step(), where the last collisions follow on the grid, the points stay in its arrays for them; where
      // this substep integrated there, for the next one's (positions_behind_)
      grid_->limitStretch(x_, displacement ? &v_ : nullptr, limit, scene_.sim.stretch_passes, enabled, wait,
                          !(in_passes_ && (collideLastOnGrid() || grid_integrate_)), grid_integrate_);
      return;
    }
  for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass)
    sweepColours([&](std::size_t, std::uint32_t s, const Spring& sp) {
      const bool pinned_a = topo_.pinned[sp.a] != 0, pinned_b = topo_.pinned[sp.b] != 0;
      const T share_a = physics::stretchShare<T>(pinned_a, pinned_b);
      const T share_b = physics::stretchShare<T>(pinned_b, pinned_a);
      const vec3 ca = physics::stretchCorrection(x_[sp.a], x_[sp.b], rest_[s], limit, share_a);
      const vec3 cb =
          share_a == share_b ? -ca : physics::stretchCorrection(x_[sp.b], x_[sp.a], rest_[s], limit, share_b);
      if (!pinned_a) displace(sp.a, ca);
      if (!pinned_b) displace(sp.b, cb);
    });
}

template <class T>
void CpuSolver<T>::limitStretchJacobi() {
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  const T limit = T(scene_.sim.stretch_limit);
  const long long n = (long long)x_.size();
  for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass) {
    // Provot (1995) per spring, gathered per vertex (Jacobi) so the GPU can do the same with no atomics.
    parallelFor(0, n, threads_, [&](long long p) {
      const std::size_t i = std::size_t(p);
      vec3 sum(0);
      int violated = 0;
      if (!topo_.pinned[i]) {
        for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
          const Neighbor& nb = topo_.adjacency[e];
          if (!enabled[int(nb.type)]) continue;
          const T share = physics::stretchShare<T>(false, topo_.pinned[nb.other] != 0);
          const vec3 c = physics::stretchCorrection(x_[i], x_[nb.other], rest_adjacent_[e], limit, share);
          if (c != vec3(0)) {
            sum += c;
            ++violated;
          }
        }
      }
      // Averaged, not summed: the springs of a hanging point mostly pull the same way, and their summed
      // Jacobi corrections overshoot and diverge (measured: strain 9.6 -> 1e52 over 64 passes).
      correction_[i] = violated > 0 ? sum / T(violated) : vec3(0);
    });
    applyCorrections();
  }
}

// The members defined here; cpu_solver.cpp instantiates the rest of the class.
template void CpuSolver<float>::limitStretch(bool);
template void CpuSolver<double>::limitStretch(bool);
template void CpuSolver<float>::limitStretchColoured(bool);
template void CpuSolver<double>::limitStretchColoured(bool);
template void CpuSolver<float>::limitStretchJacobi();
template void CpuSolver<double>::limitStretchJacobi();

}  // namespace drape
