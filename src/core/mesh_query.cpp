#include "core/mesh_query.hpp"
#include "core/triangle_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace drape {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Buckets as a CSR list: `count(add)` calls add(bucket, triangle) for every pair, twice (count, then fill).
template <class ForEach>
void buildBuckets(std::size_t buckets, ForEach for_each, std::vector<std::uint32_t>& start,
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
  const auto& x = mesh.positions;
  glm::dvec3 lo = x.front(), hi = x.front();
  for (const glm::dvec3& p : x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // About 32 cells along the largest extent: a few triangles per cell on the bundled obstacles.
  cell_ = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / 32.0;
  origin_ = lo - cell_;
  dims_ = glm::ivec3(glm::ceil((hi - lo) / cell_)) + 2;
  const std::size_t triangles = mesh.triangles.size() / 3;
  auto cellRange = [&](std::size_t t, glm::ivec3& from, glm::ivec3& to) {
    const glm::dvec3 a = x[mesh.triangles[3 * t]], b = x[mesh.triangles[3 * t + 1]], c = x[mesh.triangles[3 * t + 2]];
    from =
        glm::clamp(glm::ivec3(glm::floor((glm::min(a, glm::min(b, c)) - origin_) / cell_)), glm::ivec3(0), dims_ - 1);
    to = glm::clamp(glm::ivec3(glm::floor((glm::max(a, glm::max(b, c)) - origin_) / cell_)), glm::ivec3(0), dims_ - 1);
  };
  buildBuckets(
      std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z),
      [&](auto add) {
        for (std::size_t t = 0; t < triangles; ++t) {
          glm::ivec3 from, to;
          cellRange(t, from, to);
          for (int k = from.z; k <= to.z; ++k)
            for (int j = from.y; j <= to.y; ++j)
              for (int i = from.x; i <= to.x; ++i)
                add((std::size_t(k) * std::size_t(dims_.y) + std::size_t(j)) * std::size_t(dims_.x) + std::size_t(i),
                    std::uint32_t(t));
        }
      },
      cell_start_, cell_triangles_);
  buildBuckets(
      std::size_t(dims_.x) * std::size_t(dims_.z),
      [&](auto add) {
        for (std::size_t t = 0; t < triangles; ++t) {
          glm::ivec3 from, to;
          cellRange(t, from, to);
          for (int k = from.z; k <= to.z; ++k)
            for (int i = from.x; i <= to.x; ++i)
              add(std::size_t(k) * std::size_t(dims_.x) + std::size_t(i), std::uint32_t(t));
        }
      },
      column_start_, column_triangles_);
}

bool MeshQuery::inside(glm::dvec3 p) const {
  // The same shifted vertical line as insideMesh, so the same crossings.
  const glm::dvec2 shift = geometry::columnShift(mesh_->field.cell);
  const glm::dvec2 line(p.x + shift.x, p.z + shift.y);
  const glm::ivec2 c(glm::floor((line - glm::dvec2(origin_.x, origin_.z)) / cell_));
  if (c.x < 0 || c.y < 0 || c.x >= dims_.x || c.y >= dims_.z) return false;  // beyond every triangle's box
  const std::size_t column = std::size_t(c.y) * std::size_t(dims_.x) + std::size_t(c.x);
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

double MeshQuery::nearestIn(glm::dvec3 p, const std::uint32_t* first, const std::uint32_t* last, double best) const {
  const auto& x = mesh_->positions;
  const auto& tri = mesh_->triangles;
  for (const std::uint32_t* t = first; t != last; ++t)
    best = std::min(
        best, glm::distance(p, geometry::closestOnTriangle(p, x[tri[3 * *t]], x[tri[3 * *t + 1]], x[tri[3 * *t + 2]])));
  return best;
}

double MeshQuery::distance(glm::dvec3 p) const {
  const glm::ivec3 c(glm::floor((p - origin_) / cell_));
  if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, dims_)))
    return unsignedDistance(*mesh_, p);  // beyond the grid: every triangle
  // Rings of cells around p's cell, nearest first: every triangle beyond ring r is at least r cells away,
  // so once the nearest found is that close the search is over.
  double best = kInfinity;
  const int rings = std::max({dims_.x, dims_.y, dims_.z});
  for (int r = 0; r <= rings; ++r) {
    for (int k = c.z - r; k <= c.z + r; ++k)
      for (int j = c.y - r; j <= c.y + r; ++j)
        for (int i = c.x - r; i <= c.x + r; ++i) {
          if (std::max({std::abs(i - c.x), std::abs(j - c.y), std::abs(k - c.z)}) != r) continue;  // ring r only
          if (i < 0 || j < 0 || k < 0 || i >= dims_.x || j >= dims_.y || k >= dims_.z) continue;
          const std::size_t cell =
              (std::size_t(k) * std::size_t(dims_.y) + std::size_t(j)) * std::size_t(dims_.x) + std::size_t(i);
          best = nearestIn(p, cell_triangles_.data() + cell_start_[cell],
                           cell_triangles_.data() + cell_start_[cell + 1], best);
        }
    if (best <= r * cell_) break;
  }
  return best;
}

double fieldDistance(const DistanceField& field, glm::dvec3 p) {
  const glm::dvec3 g = (p - field.origin) / field.cell;
  if (!(g.x >= 0 && g.y >= 0 && g.z >= 0 && g.x < field.dims.x - 1 && g.y < field.dims.y - 1 && g.z < field.dims.z - 1))
    return kInfinity;
  const glm::ivec3 i(glm::floor(g));
  const glm::dvec3 t = g - glm::dvec3(i);
  auto s = [&](int dx, int dy, int dz) { return double(field.samples[field.index(i.x + dx, i.y + dy, i.z + dz)]); };
  const double x00 = glm::mix(s(0, 0, 0), s(1, 0, 0), t.x), x10 = glm::mix(s(0, 1, 0), s(1, 1, 0), t.x);
  const double x01 = glm::mix(s(0, 0, 1), s(1, 0, 1), t.x), x11 = glm::mix(s(0, 1, 1), s(1, 1, 1), t.x);
  return glm::mix(glm::mix(x00, x10, t.y), glm::mix(x01, x11, t.y), t.z);
}

}  // namespace drape
