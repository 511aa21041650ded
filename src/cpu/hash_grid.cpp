#include "cpu/hash_grid.hpp"

#include "core/derived.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/parallel.hpp"

#include <algorithm>
#include <bit>
#include <limits>
#include <type_traits>
#include <utility>

namespace drape {

template <class T>
void HashGrid<T>::build(const std::vector<vec3>& points, T cell_size) {
  std::exception_ptr failure;
  build(points, cell_size, failure);
}

// A counting sort, stable: within a bucket, points keep ascending index (the GPU builds the same). In a team each
// thread counts and places the points of its contiguous share with its own counts, offset by those of the threads
// before it, so a bucket lists thread 0's points, then thread 1's: the order of one thread. At 256^2 the build
// on one thread of a team of two left the other waiting 5% of a run. The counts are zeroed and summed into starts by
// every thread too, each a share of the buckets (on one thread, the other waited 0.2 ms a build at 256^2).
template <class T>
void HashGrid<T>::build(const std::vector<vec3>& points, T cell_size, std::exception_ptr& failure) {
  const std::size_t n = points.size();
  const auto team = std::size_t(teamSize()), t = std::size_t(teamThread());
  if (!teamSerial(failure, [&] {
        cells_.resize(n);
        bucket_.resize(n);
        slot_.resize(n);
        sorted_.resize(n);
        part_lo_.resize(team);
        part_hi_.resize(team);
        part_count_.resize(team);
      }))
    return;
  const T inv_cell_size = T(1) / cell_size;
  long long lo_point = 0, hi_point = (long long)n;
  teamShare(0, (long long)n, lo_point, hi_point);
  const auto first = std::size_t(lo_point), last = std::size_t(hi_point);
  glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  bool cells = false;
  if constexpr (std::is_same_v<T, float>)
    if (kernels_) {  // several points at once (one at a time, a floor without SSE4.1 was most of the build)
      int box[6] = {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
      kernels_->cellsOf(&points.data()->x, first, last, inv_cell_size, &cells_.data()->x, box);
      lo = glm::ivec3(box[0], box[1], box[2]);
      hi = glm::ivec3(box[3], box[4], box[5]);
      cells = true;
    }
  if (!cells)
    for (std::size_t i = first; i < last; ++i) {
      cells_[i] = cellOf(points[i], inv_cell_size);
      lo = glm::min(lo, cells_[i]);
      hi = glm::max(hi, cells_[i]);
    }
  part_lo_[t] = lo;
  part_hi_[t] = hi;
  teamBarrier();
  if (!teamSerial(failure, [&] {
        glm::ivec3 box_lo(0), box_hi(0);
        bool any = false;
        for (std::size_t k = 0; k < team; ++k)
          if (part_lo_[k].x <= part_hi_[k].x) {  // a share with points
            box_lo = any ? glm::min(box_lo, part_lo_[k]) : part_lo_[k];
            box_hi = any ? glm::max(box_hi, part_hi_[k]) : part_hi_[k];
            any = true;
          }
        // Box sides in 64 bits: clamped cells of a blown-up cloth span 2^31 each.
        const std::uint64_t box =
            std::uint64_t(std::int64_t(box_hi.x) - box_lo.x + 1) * std::uint64_t(std::int64_t(box_hi.y) - box_lo.y + 1);
        const std::uint64_t box_cells =
            box > (std::uint64_t(1) << 32) ? box : box * std::uint64_t(std::int64_t(box_hi.z) - box_lo.z + 1);
        dense_ = n > 0 && box_cells <= kDenseCells * n;
        // Else one bucket per point on average (a power of two, so the bucket is a mask of the hash) keeps
        // collisions between distinct cells rare without a table sized to the scene's extent.
        const std::uint32_t buckets = dense_ ? std::uint32_t(box_cells) : std::uint32_t(derived::hashBucketCount(n));
        mask_ = buckets - 1;
        box_min_ = box_lo;
        // Only a dense box is small enough for int sides: a blown-up cloth's spans 2^31 cells, which overflows.
        box_size_ = dense_ ? box_hi - box_lo + glm::ivec3(1) : glm::ivec3(0);
        start_.resize(std::size_t(buckets) + 1);
        if (fill_.size() < team * buckets) fill_.resize(team * buckets);
      }))
    return;
  const std::size_t buckets = start_.size() - 1;
  std::uint32_t* const mine = fill_.data() + t * buckets;
  std::fill(mine, mine + buckets, 0u);
  for (std::size_t i = first; i < last; ++i) {
    bucketOf(cells_[i], bucket_[i]);
    ++mine[bucket_[i]];
  }
  teamBarrier();
  // Each thread's buckets [b0, b1): their counts summed, then (after the threads before have summed theirs) every
  // thread's count of each made its next slot
  long long b0 = 0, b1 = (long long)buckets;
  teamShare(0, (long long)buckets, b0, b1);
  std::uint32_t total = 0;
  for (std::size_t k = 0; k < team; ++k)
    for (auto b = std::size_t(b0); b < std::size_t(b1); ++b)
      total += fill_[k * buckets + b];
  part_count_[t] = total;
  teamBarrier();
  std::uint32_t at = 0;
  for (std::size_t k = 0; k < t; ++k)
    at += part_count_[k];
  for (auto b = std::size_t(b0); b < std::size_t(b1); ++b) {
    start_[b] = at;
    for (std::size_t k = 0; k < team; ++k)
      at += std::exchange(fill_[k * buckets + b], at);
  }
  if (t + 1 == team) start_[buckets] = at;  // its share ends at the last bucket
  teamBarrier();
  for (std::size_t i = first; i < last; ++i) {
    slot_[i] = mine[bucket_[i]]++;
    sorted_[slot_[i]] = std::uint32_t(i);
  }
  teamBarrier();
}

template class HashGrid<float>;
template class HashGrid<double>;

}  // namespace drape
