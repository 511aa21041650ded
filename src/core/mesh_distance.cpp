#include "core/mesh_distance.hpp"
#include "core/mesh_query.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace drape {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool finite(glm::dvec3 p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

double closestTriangleDistance(const MeshObstacle& mesh, const std::vector<glm::dvec3>& points) {
  if (mesh.triangles.empty()) return kInfinity;
  const MeshQuery grid(mesh);
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
