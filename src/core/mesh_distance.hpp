// How close a cloth comes to a mesh obstacle, for `simulate`'s summary and `accuracy`'s penetration figure:
// the signed distance of its closest point (negative: the deepest inside). Every point against every
// triangle took 23 s for a 98k-point tablecloth, and minutes at 2048^2, so the obstacle's own structures
// answer instead:
//  - a point within the field's band of exact samples (|value| < band) takes the field's value
//    (fieldDistance, the trilinear value the solvers collide with); one such point makes the answer
//    theirs, since every other point is farther than the band;
//  - a point deeper inside takes the field's value too: beyond the band a closest-point transform, with the
//    true sign and near the exact depth (its error: docs/design.md, section 2);
//  - only when no point is within the band are exact distances needed: each point is searched outward from
//    its bucket of triangles (MeshQuery, core/mesh_query.hpp), skipping any point and any bucket that cannot
//    beat the closest distance found so far.
#pragma once

#include "core/mesh_obstacle.hpp"

#include <glm/glm.hpp>

#include <vector>

namespace drape {

// +infinity when `points` holds no finite point; non-finite points are passed over.
double closestSignedDistance(const MeshObstacle& mesh, const std::vector<glm::dvec3>& points);

// The exact unsigned distance from the closest of `points` to the triangles (the search above, for every
// point): what closestSignedDistance falls back on, and what tests hold it against.
double closestTriangleDistance(const MeshObstacle& mesh, const std::vector<glm::dvec3>& points);

}  // namespace drape
