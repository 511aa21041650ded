// The implicit integrators' sweeps of CpuSolver (docs/design.md section 2, XPBD and VBD), apart from the
// explicit passes in cpu_solver.cpp.
#include "cpu/cpu_solver.hpp"
#include "cpu/cpu_solver_sweep.hpp"
#include "cpu/parallel.hpp"

#include <type_traits>

namespace drape {

// XPBD with Small Steps (Macklin et al. 2019): many substeps of few sweeps, each spring a distance
// constraint of compliance 1/k. Gauss-Seidel over the stretch limit's colouring rather than a Jacobi
// average: a colour's springs share no point, so each sees its neighbours' latest positions (Jacobi
// needs relaxation to converge and then damps), a colour is one parallel loop here and one dispatch on
// the GPU, and the result does not depend on the thread count. The multipliers start from 0 each
// substep (Small Steps); with one sweep the stored multiplier is never read, so it is not kept.
template <class T>
void CpuSolver<T>::solveXpbd() {
  positionsMoved();
  const bool displacement = form_ == VerletForm::Displacement;
  const int iterations = scene_.sim.iterations;
  // A grid's sweeps by the grid kernels (8 springs of a colour at a time, the multipliers at the springs'
  // starts: the same bytes).
  if constexpr (std::is_same_v<T, float>)
    if (grid_) {
      const ClothSpec& c = scene_.cloth;
      const bool enabled[kSpringTypeCount] = {c.enable_structural, c.enable_shearing, c.enable_bending};
      grid_->xpbd(x_, displacement ? &v_ : nullptr, alpha_tilde_.k, enabled, iterations);
      return;
    }
  if (iterations > 1) teamSingle([&] { lambda_.assign(colouring_.springs.size(), T(0)); });
  for (int sweep = 0; sweep < iterations; ++sweep)
    sweepColours([&](std::size_t k, std::uint32_t s, const Spring& sp) {
      const bool pinned_a = topo_.pinned[sp.a] != 0, pinned_b = topo_.pinned[sp.b] != 0;
      if (pinned_a && pinned_b) return;
      const T wa = pinned_a ? T(0) : inv_mass_[sp.a];
      const T wb = pinned_b ? T(0) : inv_mass_[sp.b];
      const T lambda = iterations > 1 ? lambda_[k] : T(0);
      vec3 p;
      const T dlambda = physics::xpbdDistanceCorrection(x_[sp.a], x_[sp.b], rest_[s], wa + wb,
                                                        alpha_tilde_.k[int(sp.type)], lambda, p);
      if (iterations > 1) lambda_[k] = lambda + dlambda;
      // x_prev stays: v = x - x_prev is the constrained displacement
      if (!pinned_a) displace(sp.a, (-wa) * p);
      if (!pinned_b) displace(sp.b, wb * p);
    });
}

// Vertex Block Descent (Chen et al. 2024) on the springs: each sweep moves every free point, colour after
// colour, by a Newton step on its share of the implicit-Euler energy with its neighbours held
// (physics::vbdAddSpring, vbdStep). Points of a colour share no spring, so a colour is one parallel loop
// here and one dispatch on the GPU, and the result does not depend on the thread count. The sweeps start
// from the prediction y = x + keep v + a dt^2 (integrate): a point's own position changes only when its
// colour runs, so in the first sweep x = y and the inertia's gradient is exactly 0; later sweeps need y,
// which the first keeps. CS184's damping is in the prediction, as for XPBD.
template <class T>
void CpuSolver<T>::solveVbd() {
  positionsMoved();
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  const bool displacement = form_ == VerletForm::Displacement;
  const int iterations = scene_.sim.iterations;
  const T dt2 = dt_ * dt_;
  // A grid's sweeps by the grid kernels, 8 points of a colour at a time (the same bytes).
  if constexpr (std::is_same_v<T, float>)
    if (grid_) {
      grid_->vbd(x_, displacement ? &v_ : nullptr, stiffness_.k, enabled, dt2, iterations, point_colouring_.start);
      return;
    }
  if (iterations > 1) teamSingle([&] { inertia_target_.resize(x_.size()); });
  for (int sweep = 0; sweep < iterations; ++sweep)
    for (int colour = 0; colour < point_colouring_.colourCount(); ++colour) {
      const long long first = point_colouring_.start[std::size_t(colour)];
      const long long last = point_colouring_.start[std::size_t(colour) + 1];
      parallelFor(first, last, threads_, [&](long long k) {
        const std::size_t i = point_colouring_.points[std::size_t(k)];
        if (topo_.pinned[i]) return;
        const vec3 x = x_[i];
        const T inertia = T(1) / (inv_mass_[i] * dt2);  // m / dt^2, from the inverse mass the GPU holds
        vec3 f(0), h_off(0);
        vec3 h_diag(inertia);
        if (sweep > 0) f = (-inertia) * (x - inertia_target_[i]);
        for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
          const Neighbor& nb = topo_.adjacency[e];
          const int type = int(nb.type);
          if (enabled[type])
            physics::vbdAddSpring(x, x_[nb.other], rest_adjacent_[e], stiffness_.k[type], f, h_diag, h_off);
        }
        if (sweep == 0 && iterations > 1) inertia_target_[i] = x;
        const vec3 dx = physics::vbdStep(f, h_diag, h_off);
        x_[i] = x + dx;
        if (displacement) v_[i] += dx;  // x_prev stays: v = x - x_prev is the solved displacement
      });
    }
}

template void CpuSolver<float>::solveXpbd();
template void CpuSolver<double>::solveXpbd();
template void CpuSolver<float>::solveVbd();
template void CpuSolver<double>::solveVbd();

}  // namespace drape
