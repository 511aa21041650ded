// An allocator whose blocks start on a 64-byte cache line, for the grid path's padded arrays (GridShape): with each
// row's first point on a line as well, a vector of sixteen floats at a row's start and every kW-th point after it is
// one line, not two, and a vector of eight half of one. Not for the kernels' units (cpu/simd.hpp): nothing inline may
// be shared with them, so they never instantiate it.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace drape {

inline constexpr std::size_t kCacheLine = 64;

template <class T>
struct CacheAligned {
  using value_type = T;
  CacheAligned() = default;
  template <class U>
  CacheAligned(const CacheAligned<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(kCacheLine))); }
  void deallocate(T* p, std::size_t n) { ::operator delete(p, n * sizeof(T), std::align_val_t(kCacheLine)); }
  friend bool operator==(CacheAligned, CacheAligned) { return true; }
};

// One per thread of a team, on lines of its own: in a std::vector<Lined<T>>, what one thread writes in its element (a
// std::vector's end as it grows) shares no cache line with another thread's element.
template <class T>
struct alignas(kCacheLine) Lined {
  T value;
};

// A padded array of the grid path (GridShape's layout)
using PaddedFloats = std::vector<float, CacheAligned<float>>;

}  // namespace drape
