// CpuSolver's self-collision (selfCollide): the candidate lists and the grid stencil of
// cpu/collision_pairs.hpp, then CS184's averaged push between points closer than 2 x thickness, as a Jacobi
// pass. Kept apart from cpu_solver.cpp for its size.
#include "cpu/cpu_solver.hpp"
#include "cpu/parallel.hpp"

#include <atomic>
#include <exception>
#include <type_traits>

namespace drape {

template <class T>
void CpuSolver<T>::selfCollide() {
  const T thickness = T(scene_.cloth.thickness);
  const T range = T(2) * thickness;
  // The skin is a share of the contact distance, or of the spacing where the cloth is finer than that. On a
  // grid the stencil tests the ring of unheld pairs within range + skin at rest every substep (20 offsets at
  // 256^2 with CS184's thickness), so the skin sets both its width and how long the lists last. The bytes do
  // not depend on it.
  // Every thread of a team shares the list check and the build; an exception (out of memory) is kept for
  // step() to rethrow after the region.
  teamSingle([&] {
    try {
      pairs_.configure(range, T(pair_margin_) * std::min(range, T(shortest_spring_)));
      near_.resize(x_.size());
      pairs_.startCheck(x_);
    } catch (...) {
      failure_ = std::current_exception();
    }
  });
  if (failure_) return;
  if (pairs_.finishCheck(x_)) {
    try {
      pairs_.build(x_, threads_);
    } catch (...) {  // outside a team
      failure_ = std::current_exception();
    }
    teamSingle([&] {
      if (std::exception_ptr e = pairs_.takeFailure()) failure_ = e;
    });
    if (failure_) return;
  }
  const std::size_t stencil = pairs_.stencil().size();
  if (stencil > 0) {
    if constexpr (std::is_same_v<T, float>)
      if (grid_)
        grid_->stencilFlags(x_, pairs_.stencilDu(), pairs_.stencilDv(), pairs_.stencilMixed(), int(stencil),
                            range * range, near_);
    if (!std::is_same_v<T, float> || !grid_)
      parallelFor(0, (long long)x_.size(), threads_,
                  [&](long long p) { near_[std::size_t(p)] = pairs_.stencilMask(x_, std::size_t(p)); });
  }
  // The cells of a grid of cell size `range` fix the order of each point's sum (see forEachOrderedPair).
  const T inv_range = T(1) / range;
  const long long n = (long long)x_.size();
  const T steps = T(scene_.sim.steps_per_frame);
  // Jacobi: every correction is computed from the positions before the pass, so the result does not
  // depend on the order points are visited (nor, on the GPU, on thread order).
  std::atomic<long long> terms = 0;  // pairs in range, counted for `drape simulate -v`
  teamRange(0, n, [&](long long lo, long long hi) {
    long long mine = 0;
    for (long long p = lo; p < hi; ++p) {
      const std::size_t i = std::size_t(p);
      const int count = sumPairs(i, stencil, thickness, inv_range, steps);
      mine += count;
    }
    terms += mine;
  });
  teamSingle([&] { pair_terms_ += terms; });
  applyCorrections();
}

// One point's self-collision correction, into correction_[i]; returns how many pairs were in range.
template <class T>
int CpuSolver<T>::sumPairs(std::size_t i, std::size_t stencil, T thickness, T inv_range, T steps) {
  {
    vec3 sum(0);
    int count = 0;
    bool candidates = false;
    // Most points have no pair in range: the stencil's test and the vectorised test of the list say so
    // without the ordered sweep.
    if (!topo_.pinned[i]) {
      candidates = stencil > 0 && near_[i] != 0;
      if (!candidates && pairs_.begin(i) != pairs_.end(i)) {
        candidates = true;
        if constexpr (std::is_same_v<T, float>)
          if (kernels_) candidates = kernels_->anyInRange(&x_.data()->x, pairs_.begin(i), pairs_.end(i), i, thickness);
      }
    }
    if (candidates) {
      forEachOrderedPair(
          pairs_, i, x_, thickness, inv_range,
          [&](vec3 c) {
            sum += c;
            ++count;
          },
          stencil > 0 ? near_[i] : 0);
    }
    correction_[i] = count > 0 ? sum / (T(count) * steps) : vec3(0);
    return count;
  }
}

template void CpuSolver<float>::selfCollide();
template void CpuSolver<double>::selfCollide();
template int CpuSolver<float>::sumPairs(std::size_t, std::size_t, float, float, float);
template int CpuSolver<double>::sumPairs(std::size_t, std::size_t, double, double, double);

}  // namespace drape
