// CollisionPairs' search for a build's candidates (findPairs, findPairsByCell): the scans of the grid's cells and the
// filing of the pairs they find. Kept apart from collision_pairs_build.cpp for its size.
#include "core/memory_stage.hpp"
#include "cpu/collision_pairs.hpp"

#include <algorithm>
#include <cstdint>
#include <new>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace drape {

// PairScanArgs and GridKernels::scanPairs in T, one candidate at a time (double, or float without kernels).
template <class T>
int CollisionPairs<T>::scanSlots(const ScanArgs& a, std::uint32_t first, std::uint32_t last, std::uint32_t* out) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x,  a.y,  a.z,      a.u,  a.v,  a.px,         a.py,   a.pz,
                           a.pu, a.pv, a.reach2, a.a2, a.b2, a.near_below, a.near2};
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

// The list's tables in locals, for the loops that file a build's pairs (as members they were loaded again after every
// pair a vector stored, which may alias them): f(i, j, far), far kFarBit or 0
template <class T>
struct CollisionPairs<T>::Filer {
  Found* mine;                  // the finding thread's found_, assemblers() of them
  const std::uint32_t* bounds;  // assemble_bounds_
  bool one;                     // one share to assemble: every pair to mine[0]
  const std::uint32_t* uv;      // the columns and rows, where pairs are classed by offset (by_offset_)
  const std::int32_t* kind;     // kind_ there, else null
  int box;
  const vec3* rest;  // without the table: the rest shape, or null
  T range;
  void operator()(std::uint32_t i, std::uint32_t j, std::uint32_t far) const;
};

template <class T>
typename CollisionPairs<T>::Filer CollisionPairs<T>::filer(Found* mine) const {
  Filer f{mine, assemble_bounds_.data(), assemblers() == 1, nullptr, nullptr, box_, nullptr, range_};
  if (by_offset_) {
    f.uv = uv_.data();
    f.kind = kind_.data();
  } else if (!rest_.empty()) {
    f.rest = rest_.data();
  }
  return f;
}

// Pair {i, j} of a candidate found within reach (j in a forward cell of i's) into `mine` unless the springs hold it or
// the stencil tests it, its part told by `far` (kFarBit where its squared distance is not under the near entries'
// reach: a NaN distance is near, always tested, as the scalar sum gives such a pair its terms).
// Classed by its offset, a pair is never held at rest where the table lists it or off the box: makeStencil lists an
// offset only where its nominal distance, less the slack (the rest shape's jitter and the round-off of a distance in
// T), reaches range + margin, and the box spans that reach. So heldAtRest is asked only without the table.
template <class T>
[[gnu::always_inline]] inline void CollisionPairs<T>::Filer::operator()(std::uint32_t i, std::uint32_t j,
                                                                        std::uint32_t far) const {
  const Pair pair{std::min(i, j), std::max(i, j) | far};
  const auto keep = [&] {
    std::size_t d = 0;
    if (!one)
      while (pair.lower >= bounds[d + 1])
        ++d;
    mine[d].value.push_back(pair);
  };
  if (kind) {
    const int du = columnOf(uv[j]) - columnOf(uv[i]), dv = rowOf(uv[j]) - rowOf(uv[i]);
    if (du < -box || du > box || dv < -box || dv > box) return keep();
    const int side = 2 * box + 1;
    if (kind[std::size_t((dv + box) * side + du + box)] == kList) keep();  // else held, or on the stencil
    return;
  }
  if (!rest || !physics::heldAtRest(rest[i], rest[j], range)) keep();
}

// Each pair once (half the cell lookups), into thread t's share; the lists made from them are grouped by point and
// each point's sum orders its terms, so the bytes do not depend on how the points were split between threads nor
// in what order they were found. [lo, hi): points, or on dense buckets slots of the grid's order (findPairsByCell).
template <class T>
void CollisionPairs<T>::findPairs(const std::vector<vec3>& x, int t, long long lo, long long hi) {
  const MemoryStage stage("listing the self-collision candidates of " + std::to_string(x.size()) + " points");
  if (grid_.dense() && build_order_ == BuildOrder::ByCell) return findPairsByCell(t, lo, hi);
  const Filer file = filer(&found_[std::size_t(t) * assemblers()]);  // cleared by prepareBuild
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
          if (grid_.inCell(j, cell)) file(std::uint32_t(i), j, farMark(x[i], s));
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
    scan.pu = T(columnOf(uv_[i]));
    scan.pv = T(rowOf(uv_[i]));
  }
}

// scanCell's test in T (double, or float without kernels): scanSlots for each point at slots [p0, p1) against each
// range.
template <class T>
int CollisionPairs<T>::scanCellSlots(const ScanArgs& a, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges,
                                     int count_of, std::uint32_t* points, std::uint32_t* slots) const {
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {
      const PairScanArgs k{a.x, a.y, a.z, a.u, a.v, 0, 0, 0, 0, 0, a.reach2, a.a2, a.b2, a.near_below, a.near2};
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
      for (std::uint32_t& s : std::span(slots + count, std::size_t(found)))
        s |= farMark(vec3(at.px, at.py, at.pz), s);
      count += found;
    }
  return count;
}

// Slots [lo, hi) of the grid's order, a cell's points at a time: each of the cell's forward ranges (its own row
// first, from the cell itself) is scanned once for all of them, the ranges in one call (scanCell). A cell holds a
// few points (2.7 on selfCollision): copying its ranges into one run for each point to scan whole, as the build once
// did, cost twice the scans themselves. The scan tells each pair's part (kFarSlot), from the distance it tested.
// The pairs of many cells are filed together (fileFound): a cell's few, filed as they were found, waited on the
// loads of their points.
template <class T>
void CollisionPairs<T>::findPairsByCell(int t, long long lo, long long hi) {
  // Pairs of slots held before they are filed: an L1 cache's worth, or one cell's where it has more
  constexpr std::size_t kBatch = 2048;
  const Filer file = filer(&found_[std::size_t(t) * assemblers()]);
  std::vector<std::uint32_t>&points = cell_points_[std::size_t(t)], &slots = cell_slots_[std::size_t(t)];
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  std::size_t held = 0;
  try {
    for (long long s = lo; s < hi;) {
      if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
      const std::uint32_t at = sorted[std::size_t(s)];
      const glm::ivec3 cell = grid_.cellOfPoint(at);
      // the cell's points in this share: slots [s, e), to the end of its bucket (dense: a bucket is a cell)
      const long long e = std::min(hi, (long long)grid_.bucketEnd(at));
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
      s = e;
      if (count_of == 0) continue;
      // The points' slots, then the candidates', each with room for the vectors stored past the last pair
      if (held > 0 && held + most > kBatch) {
        fileFound(file, points.data(), slots.data(), held);
        held = 0;
      }
      if (const std::size_t room = held + most + kPairScanPad; points.size() < room) {
        points.resize(std::max(room, kBatch + kPairScanPad));
        slots.resize(points.size());
      }
      held += std::size_t(scanCellSlots(scan_, p0, p1, ranges, count_of, points.data() + held, slots.data() + held));
    }
    fileFound(file, points.data(), slots.data(), held);
  } catch (const std::bad_alloc&) {
    out_of_memory_.set = true;
  }
}

// The pairs of slots found, `count` of them, filed: by the kernels where a grid's offsets class them (the table) and
// they go to at most two shares, else one at a time.
template <class T>
void CollisionPairs<T>::fileFound(const Filer& file, const std::uint32_t* points, const std::uint32_t* slots,
                                  std::size_t count) const {
  if (count == 0) return;
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  if constexpr (std::is_same_v<T, float>)
    if (kernels_ && file.kind && assemblers() <= 2) {
      const PairFileArgs args{sorted.data(), uv_.data(), kind_.data(), box_,
                              file.one ? ~std::uint32_t(0) : file.bounds[1]};
      FiledPair* out[2] = {nullptr, nullptr};  // one share: no lower end reaches the split
      std::size_t before[2];
      const int shares = file.one ? 1 : 2;
      for (int d = 0; d < shares; ++d) {
        std::vector<Pair>& to = file.mine[d].value;
        before[d] = to.size();
        to.resize(before[d] + count + kPairScanPad);  // whole vectors stored past the last
        out[d] = to.data() + before[d];
      }
      int counts[2];
      kernels_->filePairs(args, points, slots, int(count), out, counts);
      for (int d = 0; d < shares; ++d)
        file.mine[d].value.resize(before[d] + std::size_t(counts[d]));
      return;
    }
  for (std::size_t k = 0; k < count; ++k)
    file(sorted[points[k]], sorted[slots[k] & ~kFarBit], slots[k] & kFarBit);
}

template int CollisionPairs<float>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<float>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<float>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<float>::findPairsByCell(int, long long, long long);
template int CollisionPairs<float>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                  std::uint32_t*, std::uint32_t*) const;
template int CollisionPairs<double>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<double>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<double>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<double>::findPairsByCell(int, long long, long long);
template int CollisionPairs<double>::scanCellSlots(const ScanArgs&, std::uint32_t, std::uint32_t, const CellRange*, int,
                                                   std::uint32_t*, std::uint32_t*) const;

}  // namespace drape
