// CpuSolver's forces (springs, gravity, wind), Verlet integration and tethers: the passes that move every point by
// its own neighbourhood. Kept apart from cpu_solver.cpp for its size.
#include "cpu/cpu_solver.hpp"
#include "cpu/cpu_solver_sweep.hpp"
#include "cpu/parallel.hpp"

#include <cstdint>
#include <type_traits>

namespace drape {

template <class T>
typename CpuSolver<T>::vec3 CpuSolver<T>::pointNormal(int i) const {
  const auto& s = topo_.normal_stencil[std::size_t(i)];
  return physics::gridNormal(x_[s[0]], x_[s[1]], x_[s[2]], x_[s[3]]);
}

template <class T>
void CpuSolver<T>::accumulateForces() {
  const ClothSpec& cloth = scene_.cloth;
  const WindSpec& wind = scene_.sim.wind;
  if (!in_passes_) syncPositions();
  // XPBD and VBD predict with the external forces only: their springs act in solveXpbd or solveVbd.
  const bool springs = !isImplicit(scene_.sim.integrator);
  const bool enabled[kSpringTypeCount] = {springs && cloth.enable_structural, springs && cloth.enable_shearing,
                                          springs && cloth.enable_bending};
  const vec3 gravity = vec3(scene_.sim.gravity);
  if constexpr (std::is_same_v<T, float>)
    if (grid_ && springs && !wind.enabled && grid_integrate_) {
      // and integrate in the same sweep (integrate() then only waits for it)
      grid_->forcesAndIntegrate(integratedPositionsOut(), f_, gravity, stiffness_.k, enabled, dt_ * dt_, keep_);
      return;
    }
  if constexpr (std::is_same_v<T, float>)
    if (grid_ && springs && !wind.enabled) {
      // integrate reads its own rows' forces: no barrier after them
      grid_->forces(x_, f_, gravity, stiffness_.k, enabled, false, in_passes_ && soa_positions_ == substeps_);
      return;
    }
  const T time = T(double(substeps_) * scene_.sim.dt());
  // Per point, over its adjacency in a fixed order (the GPU's). Computing each spring once and gathering
  // it from both ends gives the same bytes (springForce(b, a) is exactly -springForce(a, b)) but measured
  // 1.5x slower here: the per-spring pass scatters its reads and writes, while this loop reads one
  // point's neighbourhood, which is mostly in cache.
  const long long n = (long long)x_.size();
  // XPBD's and VBD's prediction (or a cloth with every spring type off): no neighbour to visit, and without
  // wind the force is the weight alone.
  const bool any_spring = enabled[0] || enabled[1] || enabled[2];
  if (!any_spring && !wind.enabled) {
    parallelFor(0, n, threads_, [&](long long p) { f_[std::size_t(p)] = gravity * mass_[std::size_t(p)]; });
    return;
  }
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    vec3 f = gravity * mass_[i];
    for (std::uint32_t e = topo_.offsets[i]; any_spring && e < topo_.offsets[i + 1]; ++e) {
      const Neighbor& nb = topo_.adjacency[e];
      const int type = int(nb.type);
      if (enabled[type]) f += physics::springForce(x_[i], x_[nb.other], rest_adjacent_[e], stiffness_.k[type]);
    }
    if (wind.enabled) {
      vec3 air = physics::windVelocity(x_[i], time, vec3(wind.velocity), T(wind.turbulence), T(wind.noise_scale),
                                       T(wind.noise_speed));
      vec3 disp = form_ == VerletForm::Displacement ? v_[i] : x_[i] - v_[i];
      f += physics::windForce(pointNormal(int(i)), disp / dt_, air, drag_area_[i]);
    }
    f_[i] = f;
  });
}

template <class T>
void CpuSolver<T>::integrate() {
  positionsMoved();
  const T dt2 = dt_ * dt_;
  // By pointShare in a team: the grid forces end without a barrier (runPasses)
  if constexpr (std::is_same_v<T, float>)
    if (grid_integrate_) {
      if (!forcesReadArrays()) grid_->integrate(integratedPositionsOut(), f_, dt2, keep_);  // else done with the forces
      if (!selfCollisionSparesBarrier()) teamBarrier();
      return;
    }
  if constexpr (std::is_same_v<T, float>)
    if (kernels_ && form_ == VerletForm::Displacement) {
      forPoints([&](long long lo, long long hi) {
        kernels_->integrate(&x_.data()->x, &v_.data()->x, &f_.data()->x, inv_mass3_.data(), pinned3_.data(), dt2, keep_,
                            3 * lo, 3 * hi);
      });
      return;
    }
  const auto point = [&](long long p) {
    const std::size_t i = std::size_t(p);
    if (topo_.pinned[i]) {
      if (form_ == VerletForm::Displacement)
        v_[i] = vec3(0);
      else
        v_[i] = x_[i];
      return;
    }
    if (form_ == VerletForm::Displacement) {
      v_[i] = physics::integrateVerlet(v_[i], f_[i] * inv_mass_[i], dt2, keep_);
      x_[i] += v_[i];
    } else {
      vec3 next = physics::integrateVerletPrevious(x_[i], v_[i], f_[i] * inv_mass_[i], dt2, keep_);
      v_[i] = x_[i];
      x_[i] = next;
    }
  };
  forEachPoint(point);
}

// Each free point, slot after slot, back within the stretch limit of its anchors. The anchors are pinned
// and never move here, so the points are independent and the loop is parallel.
template <class T>
void CpuSolver<T>::tether() {
  positionsMoved();
  const std::size_t slots = std::size_t(tethers_.slots);
  const T limit = T(scene_.sim.stretch_limit);
  const long long n = (long long)x_.size();
  parallelFor(0, n, threads_, [&](long long p) {
    const std::size_t i = std::size_t(p);
    if (topo_.pinned[i]) return;
    for (std::size_t s = 0; s < slots; ++s) {
      const std::uint32_t anchor = tethers_.anchor[i * slots + s];
      if (anchor == kNoAnchor) break;
      displace(i, physics::tetherCorrection(x_[i], x_[anchor], tether_rest_[i * slots + s], limit));
    }
  });
}

template CpuSolver<float>::vec3 CpuSolver<float>::pointNormal(int) const;
template CpuSolver<double>::vec3 CpuSolver<double>::pointNormal(int) const;
template void CpuSolver<float>::accumulateForces();
template void CpuSolver<double>::accumulateForces();
template void CpuSolver<float>::integrate();
template void CpuSolver<double>::integrate();
template void CpuSolver<float>::tether();
template void CpuSolver<double>::tether();

}  // namespace drape
