// The self-collision candidate lists on the GPU (glsl/sim/pairs.glsl, docs/design.md section 4): the hash
// grid they are built from, the lists, and their bookkeeping, which the GPU updates itself (pairs_prepare
// decides a rebuild without a read-back). Allocated once a scene asks for self-collision.
#pragma once

#include "core/scene.hpp"
#include "gl/objects.hpp"
#include "gpu/layout.hpp"
#include "gpu/plan.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace drape {

// The self-collision candidate lists as the GPU built them, read back for tests and the bench.
struct GpuPairs {
  std::vector<std::uint32_t> start;  // point count + 1: point i's candidates are list[start[i] .. start[i+1])
  std::vector<std::uint32_t> list;   // ascending within each point (as far as `capacity` holds them)
  std::uint32_t capacity = 0;        // entries the buffer holds
  std::uint32_t builds = 0;          // list builds so far
  bool overflow = false;             // some build needed more than the capacity
  float travel2 = 0;                 // m^2, the last build's squared safe travel
};

// The hash grid as the GPU built it (from the anchor positions of the last list build), read back for tests.
struct GpuGrid {
  std::vector<glm::ivec3> cells;         // per point
  std::vector<std::uint32_t> buckets;    // per point: hashCell(cell) & (bucket count - 1)
  std::vector<std::uint32_t> arrival;    // per point: its slot in the bucket's atomic (thread-timing) order
  std::vector<std::uint32_t> start;      // bucket count + 1 prefix sums
  std::vector<std::uint32_t> sorted;     // point indices grouped by bucket, ascending within one
  std::vector<glm::vec3> sorted_anchor;  // per slot: the copy of sorted[slot]'s anchor
};

namespace gpu {

class PairLists {
 public:
  bool allocated() const { return control_.id() != 0; }
  // The grid and list buffers for `points` points; `capacity` list entries (0: estimated from the cloth).
  // `point_groups`: the work groups of a per-point dispatch, the build's full size.
  void allocate(const ClothSpec& cloth, double pair_margin, std::uint64_t points, const ListLayout& layout,
                std::uint64_t capacity, std::uint64_t max_buffer_bytes, glm::uvec3 point_groups);
  // The next substep rebuilds the lists: after a change of thickness or margin, or a new list buffer.
  void invalidate();
  // A build that needed more entries than the buffer holds: a buffer 1.5 times the need replaces it and the
  // lists are rebuilt. Until then the points that did not fit were served from the grid, with the same result.
  // `state`: from a read-back or a frame's snapshot.
  void grow(const PairState& state, std::uint64_t max_buffer_bytes);
  void bind() const;
  const gl::Buffer& control() const { return control_; }
  // Where PairDispatch command `command`'s live group counts are in control(), for an indirect dispatch.
  static std::size_t commandOffset(std::uint32_t command);

  PairState readState() const;  // waits for the GPU
  GpuGrid readGrid(std::uint64_t points, std::uint32_t buckets) const;
  GpuPairs readPairs(std::uint64_t points) const;
  std::size_t bytes() const;

 private:
  void allocateList(std::uint64_t capacity);

  gl::Buffer points_, counts_, start_, blocks_, scatter_, sorted_;  // the hash grid
  gl::Buffer control_, anchor_, list_start_, list_;
  std::uint64_t capacity_ = 0;
};

}  // namespace gpu
}  // namespace drape
