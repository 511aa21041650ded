#include "core/penetration.hpp"
#include "core/triangle_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace drape {

namespace {

// The field's value is within 2 cells of the exact distance (docs/design.md, section 2): beyond this, surely
// outside.
constexpr double kFieldSlackCells = 2.0;
constexpr double kFar = std::numeric_limits<double>::infinity();

// What the field says of p's distance to the mesh: its estimate, or beyond the lattice (where it says
// nothing) the distance to the lattice's box, which holds the mesh: never more than the distance plus the
// slack.
double estimateDistance(const DistanceField& f, glm::dvec3 p) {
  if (const std::optional<double> d = fieldDistance(f, p)) return *d;
  const glm::dvec3 hi = f.origin + f.cell * glm::dvec3(f.dims - 1);
  return glm::length(glm::max(glm::max(f.origin - p, p - hi), glm::dvec3(0.0)));
}

}  // namespace

PenetrationGauge::PenetrationGauge(const Scene& scene, const Topology& topology, double spacing)
    : topology_(&topology), spacing_(spacing) {
  for (const SphereSpec& s : scene.spheres)
    obstacles_.push_back({nullptr, s.origin, s.radius});
  for (const MeshSpec& m : scene.meshes) {
    obstacles_.push_back({m.mesh.get(), glm::dvec3(0.0), 0.0});
    queries_.emplace_back(*m.mesh);
  }
}

Penetration PenetrationGauge::measure(const Positions& x) const {
  Penetration out;
  std::size_t query = 0;
  for (const Obstacle& o : obstacles_) {
    if (o.mesh)
      measureMesh(*o.mesh, queries_[query++], x, out);
    else
      measureSphere(o.centre, o.radius, x, out);
  }
  return out;
}

// Exact: a triangle's deepest point in a sphere is its point nearest the centre.
void PenetrationGauge::measureSphere(glm::dvec3 centre, double radius, const Positions& x, Penetration& out) const {
  for (std::size_t i = 0; i < x.size(); ++i)
    out.notePoint(int(i), glm::distance(x[i], centre) - radius);
  const auto& tri = topology_->triangles;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const glm::dvec3 p = geometry::closestOnTriangle(centre, x[tri[t]], x[tri[t + 1]], x[tri[t + 2]]);
    out.noteSurface(int(t / 3), p, radius - glm::distance(p, centre));
  }
}

// Sampled: each triangle near the mesh on a lattice of n steps along two of its sides, n such that
// neighbouring samples are at most `spacing` apart; only samples the field puts within a few cells of the
// surface are checked exactly.
void PenetrationGauge::measureMesh(const MeshObstacle& mesh, const MeshQuery& query, const Positions& x,
                                   Penetration& out) const {
  const double slack = kFieldSlackCells * mesh.field.cell;
  std::vector<double> estimate(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    estimate[i] = estimateDistance(mesh.field, x[i]);
    if (estimate[i] > slack) {
      out.nearest = std::min(out.nearest, estimate[i]);  // far from this mesh: the estimate will do
      continue;
    }
    out.notePoint(int(i), query.signedDistance(x[i]));
  }
  const auto& tri = topology_->triangles;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const glm::dvec3 a = x[tri[t]], b = x[tri[t + 1]], c = x[tri[t + 2]];
    const double longest = std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
    // Every point of the triangle is within `longest` of each corner.
    if (std::min({estimate[tri[t]], estimate[tri[t + 1]], estimate[tri[t + 2]]}) > longest + slack) continue;
    if (!(longest < 1e3)) continue;  // a blown-up cloth: not sampled
    const int n = std::max(1, int(std::ceil(longest / spacing_)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const glm::dvec3 p = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
        if (fieldDistance(mesh.field, p).value_or(kFar) > slack || !query.inside(p)) continue;
        out.noteSurface(int(t / 3), p, query.distance(p));
      }
  }
  out.surface = std::max(out.surface, out.vertex);
}

}  // namespace drape
