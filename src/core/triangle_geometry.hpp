// Point-triangle geometry shared by the mesh obstacle's bake (core/mesh_obstacle.cpp) and its exact queries
// (core/mesh_query.cpp), in double.
#pragma once

#include <glm/glm.hpp>

namespace drape::geometry {

// Closest point on triangle abc to p, by the region p projects into (vertex, edge or face).
inline glm::dvec3 closestOnTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Where the vertical line through (x, z) meets the triangle, if it does, and whether the triangle faces up
// there (+1) or down (-1). The caller shifts (x, z) off the
// sample lattice by an irrational fraction of a cell, so that no line runs exactly through an edge or a
// vertex and every crossing is counted once.
inline bool verticalCrossing(double x, double z, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, double& y, int& facing) {
  const double e0 = (b.x - a.x) * (z - a.z) - (b.z - a.z) * (x - a.x);
  const double e1 = (c.x - b.x) * (z - b.z) - (c.z - b.z) * (x - b.x);
  const double e2 = (a.x - c.x) * (z - c.z) - (a.z - c.z) * (x - c.x);
  if (!((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0))) return false;
  const double sum = e0 + e1 + e2;
  // e1, e2, e0 are twice the areas opposite a, b, c.
  y = (e1 * a.y + e2 * b.y + e0 * c.y) / sum;
  facing = glm::cross(b - a, c - a).y > 0 ? 1 : -1;
  return true;
}

// The shift of every vertical line off the sample lattice (see verticalCrossing).
inline glm::dvec2 columnShift(double cell) {
  return cell * glm::dvec2(0.5773502691896258e-3, 0.3183098861837907e-3);
}

}  // namespace drape::geometry
