#include "cpu/collision_pairs.hpp"
#include "core/memory_stage.hpp"
#include "cpu/parallel.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <utility>

namespace drape {

template <class T>
void CollisionPairs<T>::configure(T range, T margin) {
  if (range != range_ || margin != margin_) built_ = false;
  range_ = range;
  margin_ = margin;
}

template <class T>
void CollisionPairs<T>::setRest(std::vector<vec3> rest) {
  rest_ = std::move(rest);
  built_ = false;
}

template <class T>
T CollisionPairs<T>::safeTravel(T margin, T extent) {
  // Each computed distance is off by at most a few ulps of the coordinates it came from; 16 ulps of
  // the largest coordinate covers the differences, dot products and square roots of the argument.
  return T(0.5) * margin - T(16) * std::numeric_limits<T>::epsilon() * extent;
}

template <class T>
bool CollisionPairs<T>::update(const std::vector<vec3>& x, int threads) {
  if (built_ && anchor_.size() == x.size() && !stale(x)) return false;
  build(x, threads);
  return true;
}

// A pair not listed was at least range + margin apart at the build, and its distance has changed since by at
// most |d_i - d_j|, d being each point's displacement from its anchor: at most the diagonal of the box
// around every d. The lists hold while that diagonal is under the margin (2 * travel_, less round-off), so
// the motion every point shares (a cloth falling or swinging as a whole) does not wear them out; the classic
// check, each |d| under half the margin, charges it twice. At 256 x 256 (pinned2, CS184's thickness) the
// lists are built 163 times in the first 900 substeps against 289 (at 50 x 50, 44 against 68). The box is a reduction
// (min and max, in any order), so a GPU decides from it without another pass over the points.
template <class T>
bool CollisionPairs<T>::stale(const std::vector<vec3>& x) const {
  if (travel_ <= T(0)) return true;
  constexpr T kInf = std::numeric_limits<T>::infinity();
  vec3 lo(kInf), hi(-kInf);
  bool finite = true;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const vec3 d = x[i] - anchor_[i];
    // A non-finite position counts as moved (glm::min and max would pass over a NaN).
    finite = finite && glm::dot(d, d) <= kInf;
    lo = glm::min(lo, d);
    hi = glm::max(hi, d);
  }
  const vec3 box = hi - lo;
  const T limit = T(2) * travel_;
  return !finite || (!x.empty() && !(glm::dot(box, box) <= limit * limit));
}

template <class T>
void CollisionPairs<T>::build(const std::vector<vec3>& x, int threads) {
  const T reach = range_ + margin_;
  const T reach2 = reach * reach;
  grid_.build(x, reach);  // cells at least as large as the reach, so neighbouring cells hold every candidate
  const std::size_t n = x.size();
  // Each pair once (half the cell lookups), found in parallel; the lists made from them are sorted, so
  // they do not depend on how the points were split between threads.
  const MemoryStage stage("listing the self-collision candidates of " + std::to_string(n) + " points");
  found_.resize(std::size_t(threads));
  const long long count = (long long)n;
  // An exception may not leave an OpenMP region: a thread that runs out of memory says so, and the
  // caller's thread throws once the region is over.
  std::atomic<bool> out_of_memory = false;
#pragma omp parallel num_threads(teamFor(threads, count))
  {
    std::vector<Pair>& mine = found_[std::size_t(omp_get_thread_num())];
    mine.clear();
#pragma omp for schedule(static)
    for (long long p = 0; p < count; ++p) {
      if (out_of_memory.load(std::memory_order_relaxed)) continue;
      const std::size_t i = std::size_t(p);
      try {
        grid_.forEachForwardCandidate(i, [&](std::uint32_t j) {
          const vec3 d = x[i] - x[j];
          if (glm::dot(d, d) < reach2 && (rest_.empty() || !physics::heldAtRest(rest_[i], rest_[j], range_)))
            mine.push_back({std::uint32_t(i), j});
        });
      } catch (const std::bad_alloc&) {
        out_of_memory = true;
      }
    }
  }
  if (out_of_memory) {
    found_.clear();
    failAllocation();
  }
  start_.assign(n + 1, 0);
  for (const std::vector<Pair>& part : found_)
    for (const Pair& pair : part) {
      ++start_[pair.i + 1];
      ++start_[pair.j + 1];
    }
  for (std::size_t i = 0; i < n; ++i)
    start_[i + 1] += start_[i];
  list_.resize(start_[n]);
  fill_.assign(start_.begin(), start_.end() - 1);
  for (const std::vector<Pair>& part : found_)
    for (const Pair& pair : part) {
      list_[fill_[pair.i]++] = pair.j;
      list_[fill_[pair.j]++] = pair.i;
    }
#pragma omp parallel for schedule(static) num_threads(teamFor(threads, count))
  for (long long p = 0; p < count; ++p)
    std::sort(list_.data() + start_[std::size_t(p)], list_.data() + start_[std::size_t(p) + 1]);
  anchor_ = x;
  T extent = reach;
  for (const vec3& p : x)
    extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  travel_ = safeTravel(margin_, extent + margin_);
  built_ = true;
  ++rebuilds_;
}

template class CollisionPairs<float>;
template class CollisionPairs<double>;

HeldPairs heldPairsAtRest(const std::vector<glm::dvec3>& rest, double range) {
  HeldPairs out;
  if (rest.size() < 2) return out;
  HashGrid<double> grid;
  grid.build(rest, range);
  double closest2 = range * range;
  for (std::size_t i = 0; i < rest.size(); ++i)
    grid.forEachForwardCandidate(i, [&](std::uint32_t j) {
      const glm::dvec3 d = rest[i] - rest[j];
      const double d2 = glm::dot(d, d);
      if (d2 < range * range) {
        ++out.count;
        closest2 = std::min(closest2, d2);
      }
    });
  out.closest = out.count ? std::sqrt(closest2) : 0.0;
  return out;
}

}  // namespace drape
