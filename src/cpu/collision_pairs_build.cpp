// CollisionPairs' search for a build's candidates (findPairs): kept apart from collision_pairs.cpp for its size.
#include "core/memory_stage.hpp"
#include "cpu/collision_pairs.hpp"

#include <cstring>
#include <new>
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

// Pair {i, j} of a candidate found within reach (j in a forward cell of i's) into `mine` unless the springs hold it
// or the stencil tests it.
template <class T>
void CollisionPairs<T>::consider(std::uint32_t i, std::uint32_t j, std::vector<Pair>& mine) const {
  if (by_offset_) {
    const int du = int(u_[j]) - int(u_[i]), dv = int(v_[j]) - int(v_[i]);
    // Off the box no pair is held: the box spans the reach.
    if (du < -box_ || du > box_ || dv < -box_ || dv > box_) {
      mine.push_back({i, j});
      return;
    }
    const int side = 2 * box_ + 1;
    if (kind_[std::size_t((dv + box_) * side + du + box_)] != kList) return;  // held, or stencil
  }
  if (rest_.empty() || !physics::heldAtRest(rest_[i], rest_[j], range_)) mine.push_back({i, j});
}

// Each pair once (half the cell lookups), into thread t's share; the lists made from them are grouped by point and
// each point's sum orders its terms, so the bytes do not depend on how the points were split between threads nor
// in what order they were found. [lo, hi): points, or on dense buckets slots of the grid's order (findPairsByCell).
template <class T>
void CollisionPairs<T>::findPairs(const std::vector<vec3>& x, int t, long long lo, long long hi) {
  const MemoryStage stage("listing the self-collision candidates of " + std::to_string(x.size()) + " points");
  if (grid_.dense() && build_order_ == BuildOrder::ByCell) return findPairsByCell(x, t, lo, hi);
  std::vector<Pair>& mine = found_[std::size_t(t)];  // cleared by prepareBuild: a team adds chunk after chunk
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
          const std::uint32_t j = sorted[slots[std::size_t(k)]];
          if (grid_.inCell(j, cell)) consider(std::uint32_t(i), j, mine);
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

// Slots [lo, hi) of the grid's order, a cell's points at a time: the cell's forward ranges are copied once into
// one run (its own row first, from the cell itself), and each point scans the run from the slot after its own.
// One scan and one partial vector a point instead of one a range (five): the scans' lanes past a range were
// about half of those a build tested. selfCollision (2.7 points a cell) 0.96 of the time, pinned2 at 256^2 with
// CS184's thickness (34) 0.96-0.975.
template <class T>
void CollisionPairs<T>::findPairsByCell(const std::vector<vec3>& x, int t, long long lo, long long hi) {
  std::vector<Pair>& mine = found_[std::size_t(t)];
  CellRun& run = cell_runs_[std::size_t(t)];
  const std::vector<std::uint32_t>& sorted = grid_.sorted();
  ScanArgs scan = scan_;
  try {
    for (long long s = lo; s < hi;) {
      if (out_of_memory_.set.load(std::memory_order_relaxed)) return;
      const glm::ivec3 cell = grid_.cellOfPoint(sorted[std::size_t(s)]);
      // The ranges, each copied whole (positions, columns, rows) after the last
      run.ranges.clear();
      std::uint32_t count = 0, own_start = 0;
      grid_.forEachForwardRange(cell, [&](std::uint32_t first, std::uint32_t last, bool own) {
        if (own) own_start = first;
        if (first < last) run.ranges.push_back({first, last, count});
        count += last - first;
      });
      for (std::vector<T>* a : {&run.x, &run.y, &run.z, &run.u, &run.v})
        if (a->size() < count + kPairScanPad) a->resize(count + kPairScanPad);  // the pad: read, lanes dropped
      // Blocks of kCopyBlock, the last one past the range (the next range, copied after it, writes over that; the
      // arrays are padded by kPairScanPad): a range holds a few candidates, and a copy call a range cost more
      // than the scans it saved on a coarse cloth.
      for (const auto& r : run.ranges) {
        const std::pair<const std::vector<T>*, std::vector<T>*> arrays[5] = {
            {&sx_, &run.x}, {&sy_, &run.y}, {&sz_, &run.z}, {&su_, &run.u}, {&sv_, &run.v}};
        for (const auto& [from, to] : arrays)
          for (std::uint32_t k = 0; k < r.last - r.first; k += kCopyBlock)
            std::memcpy(to->data() + r.at + k, from->data() + r.first + k, sizeof(T) * kCopyBlock);
      }
      if (run.found.size() < count) run.found.resize(count);
      ScanArgs in_run = scan;
      in_run.x = run.x.data();
      in_run.y = run.y.data();
      in_run.z = run.z.data();
      in_run.u = run.u.data();
      in_run.v = run.v.data();
      for (; s < hi && grid_.cellOfPoint(sorted[std::size_t(s)]) == cell; ++s) {
        const std::uint32_t i = sorted[std::size_t(s)];
        setPoint(in_run, x, i);
        // The own row starts with the cell's own points, i's among them at its slot
        const auto first = std::uint32_t(s) + 1 - own_start;
        const int found = scanSlots(in_run, first, count, run.found.data());
        std::size_t r = 0;
        for (int k = 0; k < found; ++k) {  // the run's position back to its slot: found ascends
          const std::uint32_t at = run.found[std::size_t(k)];
          while (at >= run.ranges[r].at + (run.ranges[r].last - run.ranges[r].first))
            ++r;
          consider(i, sorted[run.ranges[r].first + (at - run.ranges[r].at)], mine);
        }
      }
    }
  } catch (const std::bad_alloc&) {
    out_of_memory_.set = true;
  }
}

template int CollisionPairs<float>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<float>::consider(std::uint32_t, std::uint32_t, std::vector<Pair>&) const;
template void CollisionPairs<float>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<float>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<float>::findPairsByCell(const std::vector<vec3>&, int, long long, long long);
template int CollisionPairs<double>::scanSlots(const ScanArgs&, std::uint32_t, std::uint32_t, std::uint32_t*) const;
template void CollisionPairs<double>::consider(std::uint32_t, std::uint32_t, std::vector<Pair>&) const;
template void CollisionPairs<double>::findPairs(const std::vector<vec3>&, int, long long, long long);
template void CollisionPairs<double>::setPoint(ScanArgs&, const std::vector<vec3>&, std::size_t) const;
template void CollisionPairs<double>::findPairsByCell(const std::vector<vec3>&, int, long long, long long);

}  // namespace drape
