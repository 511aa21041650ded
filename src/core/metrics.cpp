#include "core/metrics.hpp"

#include "core/cloth_mesh.hpp"
#include "core/mesh_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace drape {

glm::dvec3 centroid(const Positions& x) {
  glm::dvec3 sum(0);
  for (const auto& p : x)
    sum += p;
  return x.empty() ? sum : sum / double(x.size());
}

double minY(const Positions& x) {
  double m = std::numeric_limits<double>::infinity();
  for (const auto& p : x)
    m = std::min(m, p.y);
  return m;
}

double maxY(const Positions& x) {
  double m = -std::numeric_limits<double>::infinity();
  for (const auto& p : x)
    m = std::max(m, p.y);
  return m;
}

double maxDeviation(const Positions& a, const Positions& b) {
  double m = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    m = std::max(m, glm::distance(a[i], b[i]));
  return m;
}

double rmsDeviation(const Positions& a, const Positions& b) {
  double sum = 0;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i)
    sum += glm::dot(a[i] - b[i], a[i] - b[i]);
  return n ? std::sqrt(sum / double(n)) : 0.0;
}

double clothSize(const ClothSpec& cloth) {
  if (cloth.mesh) {
    glm::dvec3 lo = cloth.mesh->positions.front(), hi = lo;
    for (const glm::dvec3& x : cloth.mesh->positions) {
      lo = glm::min(lo, x);
      hi = glm::max(hi, x);
    }
    return glm::distance(lo, hi);
  }
  return std::hypot(cloth.width, cloth.height);
}

double maxStrain(const Topology& topo, const ClothSpec& cloth, const Positions& x) {
  double m = 0;
  for (const Spring& s : topo.springs)
    if (cloth.springEnabled(s.type)) m = std::max(m, glm::distance(x[s.a], x[s.b]) / s.rest - 1.0);
  return m;
}

double kineticEnergy(const Positions& displacement, double mass, double dt) {
  double sum = 0;
  for (const auto& v : displacement)
    sum += glm::dot(v, v);
  return 0.5 * mass * sum / (dt * dt);
}

std::vector<double> colliderDistances(const Scene& scene, const Positions& x) {
  std::vector<double> out;
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (const SphereSpec& s : scene.spheres) {
    double m = inf;
    for (const auto& p : x)
      m = std::min(m, glm::distance(p, s.origin) - s.radius);
    out.push_back(m);
  }
  for (const PlaneSpec& pl : scene.planes) {
    double m = inf;
    for (const auto& p : x)
      m = std::min(m, glm::dot(p - pl.point, pl.normal));
    out.push_back(m);
  }
  for (const MeshSpec& mesh : scene.meshes)
    out.push_back(closestSignedDistance(*mesh.mesh, x));
  return out;
}

bool allFinite(const Positions& x) {
  return std::all_of(x.begin(), x.end(), [](const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  });
}

}  // namespace drape
