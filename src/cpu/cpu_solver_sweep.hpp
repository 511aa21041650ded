// CpuSolver::sweepColours, which the stretch limit (cpu_solver_stretch.cpp) and XPBD (cpu_implicit.cpp) share, and
// forPoints, which the point passes share. Only the solver's own translation units include it (and parallel.hpp
// with it): they are compiled with OpenMP.
#pragma once

#include "cpu/cpu_solver.hpp"
#include "cpu/parallel.hpp"

namespace drape {

template <class T>
template <class F>
void CpuSolver<T>::forEachPoint(F&& point, bool wait) {
  if (!inTeam()) {
    parallelFor(0, (long long)x_.size(), threads_, point);
    return;
  }
  forPoints(
      [&](long long lo, long long hi) {
        for (long long p = lo; p < hi; ++p)
          point(p);
      },
      wait);
}

template <class T>
template <class F>
void CpuSolver<T>::forPoints(F&& body, bool wait) {
  if (!inTeam()) {
    body(0LL, (long long)x_.size());
    return;
  }
  long long lo, hi;
  pointShare(teamThread(), teamSize(), lo, hi);
  if (lo < hi) body(lo, hi);
  if (wait) teamBarrier();
}

template <class T>
template <class F>
void CpuSolver<T>::sweepColours(F&& f) {
  const ClothSpec& cloth = scene_.cloth;
  const bool enabled[kSpringTypeCount] = {cloth.enable_structural, cloth.enable_shearing, cloth.enable_bending};
  for (int colour = 0; colour < colouring_.colourCount(); ++colour) {
    const long long first = colouring_.start[std::size_t(colour)], last = colouring_.start[std::size_t(colour) + 1];
    parallelFor(first, last, threads_, [&](long long k) {
      const std::uint32_t s = colouring_.springs[std::size_t(k)];
      const Spring& sp = topo_.springs[s];
      if (enabled[int(sp.type)]) f(std::size_t(k), s, sp);
    });
  }
}

}  // namespace drape
