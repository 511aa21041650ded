#include "core/mesh_query.hpp"
#include "core/triangle_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace drape {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double boxDistance(glm::dvec3 p, glm::dvec3 lo, glm::dvec3 hi) {
  return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
}

// A CSR list from `for_each(add)`, which calls add(bucket, item) for every pair (twice: count, then fill).
template <class ForEach>
void buildLists(std::size_t buckets, ForEach for_each, std::vector<std::uint32_t>& start,
                std::vector<std::uint32_t>& items) {
  start.assign(buckets + 1, 0);
  for_each([&](std::size_t b, std::uint32_t) { ++start[b + 1]; });
  for (std::size_t b = 0; b < buckets; ++b)
    start[b + 1] += start[b];
  items.resize(start.back());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for_each([&](std::size_t b, std::uint32_t t) { items[next[b]++] = t; });
}

}  // namespace

MeshQuery::MeshQuery(const MeshObstacle& mesh) : mesh_(&mesh) {
  if (mesh.positions.empty()) return;
  lo_ = hi_ = mesh.positions.front();
  for (const glm::dvec3& p : mesh.positions) {
    lo_ = glm::min(lo_, p);
    hi_ = glm::max(hi_, p);
  }
  const std::size_t count = mesh.triangles.size() / 3;
  // About two triangles a bucket, at most 64 buckets an axis; a flat extent gets one bucket.
  const glm::dvec3 extent = hi_ - lo_;
  const double largest = std::max({extent.x, extent.y, extent.z});
  const double buckets = std::clamp(double(count) / 2.0, 1.0, 64.0 * 64.0 * 64.0);
  const glm::dvec3 solid = glm::max(extent, glm::dvec3(largest / 64.0));
  const double side = std::max(std::cbrt(solid.x * solid.y * solid.z / buckets), largest / 64.0);
  glm::ivec3 dims = glm::clamp(glm::ivec3(glm::ceil(extent / side)), glm::ivec3(1), glm::ivec3(64));
  // Long, thin triangles across many buckets: coarser buckets until the lists stay small.
  while (!fill(dims, 16 * count + 4096) && dims != glm::ivec3(1))
    dims = glm::max((dims + 1) / 2, glm::ivec3(1));
  const auto& x = mesh.positions;
  const auto& tri = mesh.triangles;
  buildLists(
      std::size_t(dims_.x) * std::size_t(dims_.z),
      [&](auto add) {
        for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
          const glm::dvec3 a = x[tri[t]], b = x[tri[t + 1]], c = x[tri[t + 2]];
          const glm::ivec3 from = bucketOf(glm::min(a, glm::min(b, c))), to = bucketOf(glm::max(a, glm::max(b, c)));
          for (int k = from.z; k <= to.z; ++k)
            for (int i = from.x; i <= to.x; ++i)
              add(std::size_t(k) * std::size_t(dims_.x) + std::size_t(i), std::uint32_t(t / 3));
        }
      },
      column_start_, column_triangles_);
}

double MeshQuery::lowerBound(glm::dvec3 p) const {
  return boxDistance(p, lo_, hi_);
}

bool MeshQuery::inside(glm::dvec3 p) const {
  if (column_start_.empty()) return false;
  const glm::dvec2 shift = geometry::columnShift(mesh_->field.cell);
  const glm::dvec2 line(p.x + shift.x, p.z + shift.y);
  // A line outside the mesh's box lands in a border column and crosses none of its triangles: still right.
  const glm::ivec3 c = bucketOf(glm::dvec3(line.x, lo_.y, line.y));
  const std::size_t column = std::size_t(c.z) * std::size_t(dims_.x) + std::size_t(c.x);
  const auto& x = mesh_->positions;
  const auto& tri = mesh_->triangles;
  int winding = 0;
  for (std::uint32_t k = column_start_[column]; k < column_start_[column + 1]; ++k) {
    const std::uint32_t t = column_triangles_[k];
    double y;
    int facing;
    if (geometry::verticalCrossing(line.x, line.y, x[tri[3 * t]], x[tri[3 * t + 1]], x[tri[3 * t + 2]], y, facing) &&
        y > p.y)
      winding += facing;
  }
  return winding > 0;
}

double MeshQuery::distance(glm::dvec3 p, double best) const {
  if (start_.empty()) return best;
  const glm::ivec3 c = bucketOf(p);
  for (int r = 0;; ++r) {
    best = searchRing(p, c, r, best);
    const glm::ivec3 from = c - r, to = c + r;
    if (glm::all(glm::lessThanEqual(from, glm::ivec3(0))) && glm::all(glm::greaterThanEqual(to, dims_ - 1)))
      return best;
    if (outsideDistance(p, from, to) >= best) return best;
  }
}

// Sorts the triangles into buckets; false, with nothing kept, if that takes more than `most` entries.
bool MeshQuery::fill(glm::ivec3 dims, std::size_t most) {
  dims_ = dims;
  // A flat mesh has no extent along an axis: one bucket there, of a small but usable size.
  const glm::dvec3 extent = hi_ - lo_;
  const double largest = std::max({extent.x, extent.y, extent.z, std::numeric_limits<double>::min()});
  cell_ = glm::max(extent / glm::dvec3(dims), glm::dvec3(largest * 1e-9));
  const std::size_t buckets = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
  std::size_t entries = 0;
  forEachBucketOfEachTriangle([&](std::size_t, std::uint32_t) { ++entries; });
  if (entries > most) return false;
  buildLists(
      buckets, [&](auto add) { forEachBucketOfEachTriangle(add); }, start_, triangles_);
  return true;
}

template <class F>
void MeshQuery::forEachBucketOfEachTriangle(F&& f) const {
  const auto& x = mesh_->positions;
  const auto& tri = mesh_->triangles;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const glm::dvec3 a = x[tri[t]], b = x[tri[t + 1]], c = x[tri[t + 2]];
    const glm::ivec3 from = bucketOf(glm::min(a, glm::min(b, c))), to = bucketOf(glm::max(a, glm::max(b, c)));
    for (int k = from.z; k <= to.z; ++k)
      for (int j = from.y; j <= to.y; ++j)
        for (int i = from.x; i <= to.x; ++i)
          f(index(i, j, k), std::uint32_t(t / 3));
  }
}

// Clamped before the conversion: a point far off (or a flat mesh's tiny bucket) would overflow an int.
glm::ivec3 MeshQuery::bucketOf(glm::dvec3 p) const {
  return glm::ivec3(glm::clamp(glm::floor((p - lo_) / cell_), glm::dvec3(0.0), glm::dvec3(dims_ - 1)));
}

std::size_t MeshQuery::index(int i, int j, int k) const {
  return (std::size_t(k) * std::size_t(dims_.y) + std::size_t(j)) * std::size_t(dims_.x) + std::size_t(i);
}

// The buckets whose index differs from c by exactly r along some axis (and at most r along the others).
double MeshQuery::searchRing(glm::dvec3 p, glm::ivec3 c, int r, double best) const {
  const auto visit = [&](int i, int j, int k) {
    const glm::dvec3 lo = lo_ + glm::dvec3(i, j, k) * cell_;
    if (boxDistance(p, lo, lo + cell_) >= best) return;
    const std::size_t b = index(i, j, k);
    for (std::uint32_t s = start_[b]; s < start_[b + 1]; ++s)
      best = std::min(best, triangleDistance(*mesh_, triangles_[s], p));
  };
  const glm::ivec3 from = glm::max(c - r, glm::ivec3(0)), to = glm::min(c + r, dims_ - 1);
  for (int k = from.z; k <= to.z; ++k)
    for (int j = from.y; j <= to.y; ++j) {
      if (std::abs(k - c.z) == r || std::abs(j - c.y) == r) {
        for (int i = from.x; i <= to.x; ++i)
          visit(i, j, k);
        continue;
      }
      if (c.x - r >= 0) visit(c.x - r, j, k);
      if (c.x + r < dims_.x) visit(c.x + r, j, k);
    }
  return best;
}

// How near p any bucket outside the block [from, to] may be: the grid's box cut at one face of the block,
// the nearest of the (up to six) pieces beyond.
double MeshQuery::outsideDistance(glm::dvec3 p, glm::ivec3 from, glm::ivec3 to) const {
  double nearest = kInfinity;
  for (int a = 0; a < 3; ++a) {
    if (to[a] < dims_[a] - 1) {
      glm::dvec3 lo = lo_;
      lo[a] = lo_[a] + (to[a] + 1) * cell_[a];
      nearest = std::min(nearest, boxDistance(p, lo, hi_));
    }
    if (from[a] > 0) {
      glm::dvec3 hi = hi_;
      hi[a] = lo_[a] + from[a] * cell_[a];
      nearest = std::min(nearest, boxDistance(p, lo_, hi));
    }
  }
  return nearest;
}

}  // namespace drape
