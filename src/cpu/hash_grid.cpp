#include "cpu/hash_grid.hpp"

#include "core/derived.hpp"

#include <bit>

namespace drape {

template <class T>
void HashGrid<T>::build(const std::vector<vec3>& points, T cell_size) {
  const std::size_t n = points.size();
  // One bucket per point on average (a power of two, so the bucket is a mask of the hash) keeps
  // collisions between distinct cells rare without a table sized to the scene's extent.
  const std::uint32_t buckets = std::uint32_t(derived::hashBucketCount(n));
  mask_ = buckets - 1;
  cells_.resize(n);
  start_.assign(std::size_t(buckets) + 1, 0);
  sorted_.resize(n);
  std::vector<std::uint32_t>& bucket = bucket_;
  bucket.resize(n);
  const T inv_cell_size = T(1) / cell_size;
  for (std::size_t i = 0; i < n; ++i) {
    cells_[i] = cellOf(points[i], inv_cell_size);
    bucket[i] = physics::hashCell(cells_[i]) & mask_;
    ++start_[bucket[i] + 1];
  }
  for (std::uint32_t b = 0; b < buckets; ++b)
    start_[b + 1] += start_[b];
  // Counting sort, stable: within a bucket, points keep ascending index (the GPU builds the same).
  fill_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    sorted_[fill_[bucket[i]]++] = std::uint32_t(i);
}

template class HashGrid<float>;
template class HashGrid<double>;

}  // namespace drape
