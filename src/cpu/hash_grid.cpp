#include "cpu/hash_grid.hpp"

#include "core/derived.hpp"

#include <bit>

namespace drape {

template <class T>
void HashGrid<T>::build(const std::vector<vec3>& points, T cell_size) {
  const std::size_t n = points.size();
  cells_.resize(n);
  const T inv_cell_size = T(1) / cell_size;
  glm::ivec3 lo(0), hi(0);
  for (std::size_t i = 0; i < n; ++i) {
    cells_[i] = cellOf(points[i], inv_cell_size);
    lo = i == 0 ? cells_[i] : glm::min(lo, cells_[i]);
    hi = i == 0 ? cells_[i] : glm::max(hi, cells_[i]);
  }
  // Box sides in 64 bits: clamped cells of a blown-up cloth span 2^31 each.
  const std::uint64_t box = std::uint64_t(std::int64_t(hi.x) - lo.x + 1) * std::uint64_t(std::int64_t(hi.y) - lo.y + 1);
  const std::uint64_t box_cells =
      box > (std::uint64_t(1) << 32) ? box : box * std::uint64_t(std::int64_t(hi.z) - lo.z + 1);
  dense_ = n > 0 && box_cells <= kDenseCells * n;
  // Else one bucket per point on average (a power of two, so the bucket is a mask of the hash) keeps
  // collisions between distinct cells rare without a table sized to the scene's extent.
  const std::uint32_t buckets = dense_ ? std::uint32_t(box_cells) : std::uint32_t(derived::hashBucketCount(n));
  mask_ = buckets - 1;
  box_min_ = lo;
  // Only a dense box is small enough for int sides: a blown-up cloth's spans 2^31 cells, which overflows.
  box_size_ = dense_ ? hi - lo + glm::ivec3(1) : glm::ivec3(0);
  start_.assign(std::size_t(buckets) + 1, 0);
  sorted_.resize(n);
  std::vector<std::uint32_t>& bucket = bucket_;
  bucket.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    bucketOf(cells_[i], bucket[i]);
    ++start_[bucket[i] + 1];
  }
  for (std::uint32_t b = 0; b < buckets; ++b)
    start_[b + 1] += start_[b];
  // Counting sort, stable: within a bucket, points keep ascending index (the GPU builds the same).
  fill_.assign(start_.begin(), start_.end() - 1);
  slot_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    slot_[i] = fill_[bucket[i]]++;
    sorted_[slot_[i]] = std::uint32_t(i);
  }
}

template class HashGrid<float>;
template class HashGrid<double>;

}  // namespace drape
