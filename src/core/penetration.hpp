// How far a cloth is inside the scene's solid obstacles (spheres and meshes; planes are two-sided and have no
// inside), measured against the exact surfaces, not the distance field the solvers collide with: the deepest
// cloth point, and the deepest point of any cloth triangle, sampled densely over each triangle (a mesh
// obstacle's edge can pass through a triangle between its corners) or, for a sphere, exact. What `drape
// penetration` reports per frame and the contact tests assert.
#pragma once

#include "core/mesh_query.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace drape {

struct Penetration {
  double vertex = 0.0;  // m: depth of the deepest cloth point inside an obstacle (0: none inside)
  int vertex_index = -1;
  int vertices_inside = 0;  // cloth points inside an obstacle
  double surface = 0.0;     // m: depth of the deepest point of any cloth triangle, corners included (>= vertex)
  glm::dvec3 surface_point{0.0};
  int surface_triangle = -1;
  // m: the smallest signed distance of a cloth point to an obstacle (negative: inside), to tell contact.
  double nearest = std::numeric_limits<double>::infinity();

  // Cloth point `index` at signed distance d from an obstacle (negative: inside).
  void notePoint(int index, double d) {
    nearest = std::min(nearest, d);
    vertices_inside += d < 0;
    if (-d > vertex) {
      vertex = -d;
      vertex_index = index;
    }
  }
  // A point p of cloth triangle `triangle` `depth` inside an obstacle.
  void noteSurface(int triangle, glm::dvec3 p, double depth) {
    if (!(depth > surface)) return;  // a NaN depth is no record
    surface = depth;
    surface_point = p;
    surface_triangle = triangle;
  }
};

class PenetrationGauge {
 public:
  // spacing: the largest distance between two neighbouring sample points of a triangle (m).
  PenetrationGauge(const Scene& scene, const Topology& topology, double spacing = 1e-3);
  Penetration measure(const Positions& x) const;

 private:
  struct Obstacle {
    const MeshObstacle* mesh = nullptr;  // or a sphere:
    glm::dvec3 centre{0.0};
    double radius = 0.0;
  };
  const Topology* topology_;
  double spacing_;
  std::vector<Obstacle> obstacles_;
  std::vector<MeshQuery> queries_;  // one per mesh obstacle, in obstacles_' order
  void measureMesh(const MeshObstacle& mesh, const MeshQuery& query, const Positions& x, Penetration& out) const;
  void measureSphere(glm::dvec3 centre, double radius, const Positions& x, Penetration& out) const;
};

}  // namespace drape
