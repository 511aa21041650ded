#include "gpu/pair_lists.hpp"

#include <algorithm>
#include <cstddef>

namespace drape::gpu {

namespace {

// List entries to allocate before any build has counted them: the points within reach in a flat sheet of the
// cloth's spacing (pi r^2 / spacing^2), four times over for folds, at least 32 per point, and no more than one
// buffer may hold. A build that needs more still gives the right answer (self_collide serves the points that
// did not fit from the grid), and the next health read grows the buffer.
std::uint64_t capacityEstimate(const ClothSpec& c, double pair_margin, std::uint64_t n, std::uint64_t limit) {
  const double spacing = std::max(
      1e-9, std::min(c.width / std::max(1, c.num_width_points - 1), c.height / std::max(1, c.num_height_points - 1)));
  const double reach = 2.0 * c.thickness * (1.0 + pair_margin);
  const double per_point = std::min(1e6, 4.0 * 3.14159265358979 * (reach / spacing) * (reach / spacing));
  const std::uint64_t wanted = n * std::max<std::uint64_t>(32, std::uint64_t(per_point));
  return std::max<std::uint64_t>(1, std::min({wanted, limit / sizeof(std::uint32_t), std::uint64_t(0xffffffffu)}));
}

}  // namespace

void PairLists::allocate(const ClothSpec& cloth, double pair_margin, std::uint64_t points, const ListLayout& layout,
                         std::uint64_t capacity, std::uint64_t max_buffer_bytes, glm::uvec3 point_groups) {
  const std::size_t n = std::size_t(points), buckets = layout.buckets;
  points_ = gl::Buffer::create(n * sizeof(GridPoint), nullptr, 0);
  // Counted into with atomics, then zeroed by the scan that reads them: zero once here. The lists' per-point
  // counts use it too.
  counts_ = gl::Buffer::create(std::max(buckets, n) * sizeof(std::uint32_t), nullptr, 0);
  counts_.clear();
  start_ = gl::Buffer::create((buckets + 1) * sizeof(std::uint32_t), nullptr, 0);
  // Shared by the bucket scan and the lists' point scan.
  blocks_ =
      gl::Buffer::create(std::max(layout.scan_blocks, layout.point_scan_blocks) * sizeof(std::uint32_t), nullptr, 0);
  scatter_ = gl::Buffer::create(n * sizeof(std::uint32_t), nullptr, 0);
  sorted_ = gl::Buffer::create(n * sizeof(GridEntry), nullptr, 0);

  control_ = gl::Buffer::create(sizeof(PairControl), nullptr, GL_DYNAMIC_STORAGE_BIT);
  control_.clear();
  anchor_ = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, 0);
  list_start_ = gl::Buffer::create((n + 1) * sizeof(std::uint32_t), nullptr, 0);
  allocateList(capacity ? capacity : capacityEstimate(cloth, pair_margin, points, max_buffer_bytes));

  // The build's dispatch sizes; the prepare kernel copies them into `live` when the lists are stale.
  PairDispatch dispatch{};
  const auto set = [&](std::uint32_t command, glm::uvec3 groups) {
    for (int k = 0; k < 3; ++k) {
      dispatch.full[3 * command + std::uint32_t(k)] = groups[k];
      dispatch.live[3 * command + std::uint32_t(k)] = groups[k];
    }
  };
  set(kPairDispatchPoints, point_groups);
  set(kPairDispatchOne, {1, 1, 1});
  set(kPairDispatchGridBlocks, {layout.scan_blocks, 1, 1});
  set(kPairDispatchPointBlocks, {layout.point_scan_blocks, 1, 1});
  control_.upload(offsetof(PairControl, dispatch), sizeof dispatch, &dispatch);
  invalidate();
}

void PairLists::allocateList(std::uint64_t capacity) {
  list_ = gl::Buffer::create(capacity * sizeof(std::uint32_t), nullptr, 0);
  capacity_ = capacity;
}

// Writes stale, travel2 and capacity; the build count and the overflow flag stay.
void PairLists::invalidate() {
  if (!allocated()) return;
  const std::uint32_t stale = 1, capacity = std::uint32_t(capacity_);
  const float no_travel = -1.0f;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  control_.upload(offsetof(PairState, stale), sizeof stale, &stale);
  control_.upload(offsetof(PairState, travel2), sizeof no_travel, &no_travel);
  control_.upload(offsetof(PairState, capacity), sizeof capacity, &capacity);
}

// A snapshot older than the last growth asks for no more than the buffer now holds, so it changes nothing.
void PairLists::grow(const PairState& state, std::uint64_t max_buffer_bytes) {
  if (!allocated() || state.overflow == 0) return;
  const std::uint64_t limit = max_buffer_bytes / sizeof(std::uint32_t);
  const std::uint64_t wanted = std::min(std::uint64_t(state.total) + state.total / 2, limit);
  if (wanted <= capacity_) return;  // grown already, or as large as allowed: the grid serves the rest
  const std::uint32_t clear = 0;
  control_.upload(offsetof(PairState, overflow), sizeof clear, &clear);
  allocateList(wanted);
  invalidate();
}

void PairLists::bind() const {
  if (!allocated()) return;
  points_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridPoints);
  counts_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridCounts);
  start_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridStart);
  blocks_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridBlocks);
  scatter_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridScatter);
  sorted_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingGridSorted);
  control_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPairControl);
  anchor_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPairAnchor);
  list_start_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPairStart);
  list_.bindBase(GL_SHADER_STORAGE_BUFFER, kBindingPairList);
}

std::size_t PairLists::commandOffset(std::uint32_t command) {
  return offsetof(PairControl, dispatch) + offsetof(PairDispatch, live) + 3 * command * sizeof(std::uint32_t);
}

PairState PairLists::readState() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  return control_.download<PairState>(1)[0];
}

GpuGrid PairLists::readGrid(std::uint64_t points, std::uint32_t buckets) const {
  GpuGrid grid;
  if (!allocated()) return grid;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const std::size_t n = std::size_t(points);
  for (const GridPoint& g : points_.download<GridPoint>(n)) {
    grid.cells.emplace_back(g.cell_x, g.cell_y, g.cell_z);
    grid.buckets.push_back(g.bucket);
    grid.arrival.push_back(g.arrival);
  }
  grid.start = start_.download<std::uint32_t>(std::size_t(buckets) + 1);
  for (const GridEntry& e : sorted_.download<GridEntry>(n)) {
    grid.sorted.push_back(e.index);
    grid.sorted_anchor.emplace_back(e.x, e.y, e.z);
  }
  return grid;
}

GpuPairs PairLists::readPairs(std::uint64_t points) const {
  GpuPairs pairs;
  if (!allocated()) return pairs;
  const PairState state = readState();
  pairs.capacity = state.capacity;
  pairs.builds = state.builds;
  pairs.overflow = state.overflow != 0;
  pairs.travel2 = state.travel2;
  pairs.start = list_start_.download<std::uint32_t>(std::size_t(points) + 1);
  pairs.list = list_.download<std::uint32_t>(std::min<std::size_t>(pairs.start.back(), state.capacity));
  return pairs;
}

std::size_t PairLists::bytes() const {
  std::size_t total = 0;
  for (const gl::Buffer* b :
       {&points_, &counts_, &start_, &blocks_, &scatter_, &sorted_, &control_, &anchor_, &list_start_, &list_})
    total += b->size();
  return total;
}

}  // namespace drape::gpu
