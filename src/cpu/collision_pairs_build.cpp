// CollisionPairs' search for a build's candidates (findPairs): kept apart from collision_pairs.cpp for its size.
#include "core/memory_stage.hpp"
#include "cpu/collision_pairs.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <span>
#include <string>
#include <type_traits>
#include <utility>

namespace drape {

// PairScanArgs and GridKernels::scanPairs in T, one candidate at a time (double, or float without kernels).
template <class T>
int CollisionPairs<T>::scanSlots(const ScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x, a.y, a.z, a.u, a.v, a.px, a.py, a.pz, a.pu, a.pv, a.reach2, a.a2, a.b2, a.near_below};
      return kernels_->scanPairs(k, first, last, out);
    }
  int count = 0;
  for (std::uint32_t s = first; s < last; ++s) {
    const T dx = a.px - a.x[s], dy = a.py - a.y[s], dz = a.pz - a.z[s];
    if (!(dx * dx + dy * dy + dz * dz < a.reach2)) continue;
    const T du = a.u[s] - a.pu, dv = a.v[s] - a.pv;
    const T nominal = du * du * a.a2 + dv * dv * a.b2;
    if (nominal < a.near_below) continue;
    out[count++] = s;
  }
  return count;
}

// Pair {i, j} of a candidate found within reach (j in a forward cell of i's), at squared distance d2, into `mine`
// unless the springs hold it or the stencil tests it: near, or far where d2 is not under the near entries' reach
// (a NaN distance is near: always tested, as the scalar sum gives such a pair its terms).
template <class T>
void CollisionPairs<T>::consider(std::uint32_t i, std::uint32_t j, T d2, Found* mine) const {
  const Pair pair{std::min(i, j), std::max(i, j) | (d2 >= near_reach_ * near_reach_ ? kFarBit : 0)};
  const auto keep = [&] {
    std::size_t d = 0;
    while (pair.lower >= assemble_bounds_[d + 1])
      ++d;
    mine[d].value.push_back(pair);
  };
  if (by_offset_) {
    const int du = int(u_[j]) - int(u_[i]), dv = int(v_[j]) - int(v_[i]);
    // Off the box no pair is held: the box spans the reach.
    if (du < -box_ || du > box_ || dv < -box_ || dv > box_) return keep();
    const int side = 2 * box_ + 1;
    if (kind_[std::size_t((dv + box_) * side + du + box_)] != kList) return;  // held, or stencil
  }
  if (rest_.empty() || !physics::heldAtRest(rest_[i], rest_[j], range_)) keep();
}

// Each pair once (half the cell lookups), into thread t's share; the lists made from them are grouped by point and
// each point's sum orders its terms, so the bytes do not depend on how the points were split between threads nor
// in what order they were found. [lo, hi): points, or on dense buckets slots of the grid's order (findPairsByCell).
template <class T>
void CollisionPairs<T>::findPairs(const std::vector<vec3>& x, int t, long long lo, long long hi) {
  const MemoryStage stage("listing the self-collision candidates of " + std::to_string(x.size()) + " points");
  if (grid_.dense() && build_order_ == BuildOrder::ByCell) return findPairsByCell(t, lo, hi);
  Found* const mine = &found_[std::size_t(t) * assemblers_];  // cleared by prepareBuild
  std::vector<std::uint32_t> slots;
  ScanArgs scan = scan_;
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  for (long long p = lo; p < hi; ++p) {
    if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
    const std::size_t i = std::size_t(p);
    try {
      setPoint(scan, x, i);
      grid_.forEachForwardBucket(i, [&](std::uint32_t first, std::uint32_t last, glm::ivec3 cell) {
        if (slots.size() < last - first) slots.resize(last - first);
        const int found = scanSlots(scan, first, last, slots.data());
        for (int k = 0; k < found; ++k) {
          const std::uint32_t s = slots[std::size_t(k)], j = sorted[s];
          if (grid_.inCell(j, cell)) consider(std::uint32_t(i), j, squaredDistance(x[i], s), mine);
        }
      });
    } catch (const std::bad_alloc&) {
      out_of_memory_.set = true;
    }
  }
}

template <class T>
void CollisionPairs<T>::setPoint(ScanArgs& scan, const std::vector<vec3>& x, std::size_t i) const {
  scan.px = x[i].x;
  scan.py = x[i].y;
  scan.pz = x[i].z;
  if (by_offset_) {
    scan.pu = T(u_[i]);
    scan.pv = T(v_[i]);
  }
}

// scanCell's test in T (double, or float without kernels): scanSlots for each point at slots [p0, p1) against each
// range.
template <class T>
int CollisionPairs<T>::scanCellSlots(const ScanArgs& a, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges,
                                     int count_of, std::uint32_t* points, std::uint32_t* slots) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x, a.y, a.z, a.u, a.v, 0, 0, 0, 0, 0, a.reach2, a.a2, a.b2, a.near_below};
      return kernels_->scanCell(k, p0, p1, ranges, count_of, points, slots);
    }
  int count = 0;
  for (const CellRange& range : std::span(ranges, std::size_t(count_of)))
    for (std::uint32_t p = p0; p < p1; ++p) {
      ScanArgs at = a;
      at.px = a.x[p];
      at.py = a.y[p];
      at.pz = a.z[p];
      at.pu = a.u[p];
      at.pv = a.v[p];
      const std::uint32_t from = range.own ? std::max(range.first, p + 1) : range.first;
      if (from >= range.last) continue;
      const int found = scanSlots(at, from, range.last, slots + count);
      std::fill(points + count, points + count + found, p);
      count += found;
    }
  return count;
}

// Slots [lo, hi) of the grid's order, a cell's points at a time: each of the cell's forward ranges (its own row
// first, from the cell itself) is scanned once for all of them, the ranges in one call (scanCell). A cell holds a
// few points (2.7 on selfCollision): copying its ranges into one run for each point to scan whole, as the build once
// did, cost twice the scans themselves.
template <class T>
void CollisionPairs<T>::findPairsByCell(int t, long long lo, long long hi) {
  Found* const mine = &found_[std::size_t(t) * assemblers_];
  std::vector<std::uint32_t>& found = cell_found_[std::size_t(t)];
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  try {
    for (long long s = lo; s < hi;) {
      if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
      const glm::ivec3 cell = grid_.cellOfPoint(sorted[std::size_t(s)]);
      long long e = s + 1;  // the cell's points in this share: slots [s, e)
      while (e < hi && grid_.cellOfPoint(sorted[std::size_t(e)]) == cell)
        ++e;
      const auto p0 = std::uint32_t(s), p1 = std::uint32_t(e);
      CellRange ranges[kCellRanges];
      int count_of = 0;
      std::size_t most = 0;
      grid_.forEachForwardRange(cell, [&](std::uint32_t first, std::uint32_t last, bool own) {
        if (own) first = p0 + 1;  // the own row from the slot after the first point
        if (first >= last) return;
        ranges[count_of++] = {first, last, own};
        most += std::size_t(p1 - p0) * (last - first);
      });
      // The points' slots, then the candidates', each with room for the vectors stored past the last pair
      const std::size_t room = most + kPairScanPad;
      if (found.size() < 2 * room) found.resize(2 * room);
      std::uint32_t *const points = found.data(), *const slots = found.data() + room;
      const int pairs = count_of > 0 ? scanCellSlots(scan_, p0, p1, ranges, count_of, points, slots) : 0;
      for (int k = 0; k < pairs; ++k)
        consider(sorted[points[k]], sorted[slots[k]],
                 squaredDistance(vec3(sx_[points[k]], sy_[points[k]], sz_[points[k]]), slots[k]), mine);
      s = e;
    }
  } catch (const std::bad_alloc&) {
    out_of_memory_.set = true;
  }
}

template int CollisionPairs<float>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<float>::consider(std::uint32_t, std::uint32_t, float, Found*) const;
template void CollisionPairs<float>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<float>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<float>::findPairsByCell(int, long long, long long);
template int CollisionPairs<float>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                  std::uint32_t*, std::uint32_t*) const;
template int CollisionPairs<double>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<double>::consider(std::uint32_t, std::uint32_t, double, Found*) const;
template void CollisionPairs<double>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<double>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<double>::findPairsByCell(int, long long, long long);
template int CollisionPairs<double>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                   std::uint32_t*, std::uint32_t*) const;

}  // namespace drape
