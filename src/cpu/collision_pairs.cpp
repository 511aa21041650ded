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
  if (built_ && anchor_.size() == x.size() && !stale(x, threads)) return false;
  build(x, threads);
  return true;
}

template <class T>
bool CollisionPairs<T>::stale(const std::vector<vec3>& x, int threads) const {
  if (travel_ <= T(0)) return true;
  const T limit2 = travel_ * travel_;
  const long long n = (long long)x.size();
  bool moved = false;
  // `!(d2 <= limit2)` so that a non-finite position also counts as moved.
#pragma omp parallel for schedule(static) num_threads(teamFor(threads, n)) reduction(|| : moved)
  for (long long i = 0; i < n; ++i) {
    const vec3 d = x[std::size_t(i)] - anchor_[std::size_t(i)];
    moved = moved || !(glm::dot(d, d) <= limit2);
  }
  return moved;
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
