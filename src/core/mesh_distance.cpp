#include "core/mesh_distance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace drape {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool finite(glm::dvec3 p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

double boxDistance(glm::dvec3 p, glm::dvec3 lo, glm::dvec3 hi) {
  return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
}

// The obstacle's triangles in a grid of buckets over its bounding box (each triangle in every bucket its
// bounding box meets), searched outward from a point's bucket in rings: a ring is visited only while the
// part of the grid outside the rings already seen may hold something nearer than the best so far.
class TriangleGrid {
 public:
  explicit TriangleGrid(const MeshObstacle& mesh) : mesh_(mesh) {
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
  }

  double lowerBound(glm::dvec3 p) const { return boxDistance(p, lo_, hi_); }

  // min(best, the distance from p to the nearest triangle).
  double distance(glm::dvec3 p, double best) const {
    const glm::ivec3 c = bucketOf(p);
    for (int r = 0;; ++r) {
      best = searchRing(p, c, r, best);
      const glm::ivec3 from = c - r, to = c + r;
      if (glm::all(glm::lessThanEqual(from, glm::ivec3(0))) && glm::all(glm::greaterThanEqual(to, dims_ - 1)))
        return best;
      if (outsideDistance(p, from, to) >= best) return best;
    }
  }

 private:
  // Sorts the triangles into buckets; false, with nothing kept, if that takes more than `most` entries.
  bool fill(glm::ivec3 dims, std::size_t most) {
    dims_ = dims;
    // A flat mesh has no extent along an axis: one bucket there, of a small but usable size.
    const glm::dvec3 extent = hi_ - lo_;
    const double largest = std::max({extent.x, extent.y, extent.z, std::numeric_limits<double>::min()});
    cell_ = glm::max(extent / glm::dvec3(dims), glm::dvec3(largest * 1e-9));
    const std::size_t buckets = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
    start_.assign(buckets + 1, 0);
    std::size_t entries = 0;
    forEachBucketOfEachTriangle([&](std::size_t bucket, std::uint32_t) {
      ++start_[bucket + 1];
      ++entries;
    });
    if (entries > most) return false;
    for (std::size_t b = 0; b < buckets; ++b)
      start_[b + 1] += start_[b];
    triangles_.resize(entries);
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    forEachBucketOfEachTriangle([&](std::size_t bucket, std::uint32_t t) { triangles_[next[bucket]++] = t; });
    return true;
  }

  template <class F>
  void forEachBucketOfEachTriangle(F&& f) const {
    const auto& x = mesh_.positions;
    const auto& tri = mesh_.triangles;
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
  glm::ivec3 bucketOf(glm::dvec3 p) const {
    return glm::ivec3(glm::clamp(glm::floor((p - lo_) / cell_), glm::dvec3(0.0), glm::dvec3(dims_ - 1)));
  }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(dims_.y) + std::size_t(j)) * std::size_t(dims_.x) + std::size_t(i);
  }

  // The buckets whose index differs from c by exactly r along some axis (and at most r along the others).
  double searchRing(glm::dvec3 p, glm::ivec3 c, int r, double best) const {
    const auto visit = [&](int i, int j, int k) {
      const glm::dvec3 lo = lo_ + glm::dvec3(i, j, k) * cell_;
      if (boxDistance(p, lo, lo + cell_) >= best) return;
      const std::size_t b = index(i, j, k);
      for (std::uint32_t s = start_[b]; s < start_[b + 1]; ++s)
        best = std::min(best, triangleDistance(mesh_, triangles_[s], p));
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
  double outsideDistance(glm::dvec3 p, glm::ivec3 from, glm::ivec3 to) const {
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

  const MeshObstacle& mesh_;
  glm::dvec3 lo_{0.0}, hi_{0.0}, cell_{1.0};
  glm::ivec3 dims_{1};
  std::vector<std::uint32_t> start_, triangles_;
};

}  // namespace

double closestTriangleDistance(const MeshObstacle& mesh, const std::vector<glm::dvec3>& points) {
  if (mesh.triangles.empty()) return kInfinity;
  const TriangleGrid grid(mesh);
  // The point nearest the obstacle's box first, so that the bound prunes the rest from the start.
  std::size_t first = points.size();
  double first_bound = kInfinity;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (finite(points[i]) && grid.lowerBound(points[i]) < first_bound) {
      first = i;
      first_bound = grid.lowerBound(points[i]);
    }
  if (first == points.size()) return kInfinity;
  double best = grid.distance(points[first], kInfinity);
  for (const glm::dvec3& p : points)
    if (finite(p) && grid.lowerBound(p) < best) best = grid.distance(p, best);
  return best;
}

double closestSignedDistance(const MeshObstacle& mesh, const std::vector<glm::dvec3>& points) {
  const DistanceField& field = mesh.field;
  // A value this far inside the band is interpolated from exact samples only: its eight samples are each
  // within a cell diagonal (under 2 cells) of the point.
  const double trusted = field.band - 2.0 * field.cell;
  double closest = kInfinity;
  bool any = false;
  for (const glm::dvec3& p : points) {
    if (!finite(p)) continue;
    any = true;
    if (const std::optional<double> d = fieldDistance(field, p); d && *d < trusted) closest = std::min(closest, *d);
  }
  if (closest < kInfinity || !any) return closest;
  // Every point is farther out than the trusted band: exact distances, outside (no point is inside).
  return closestTriangleDistance(mesh, points);
}

}  // namespace drape
