// Static meshes for the colliders, in the layout the renderer pulls vertices from (one std430 array
// per attribute, indexed by gl_VertexID): spheres by latitude/longitude, planes as one large quad.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace drape {

struct MeshData {
  std::vector<glm::vec4> positions;  // w = 1
  std::vector<glm::vec4> normals;    // unit, w = 0
  std::vector<glm::vec4> tangents;   // unit dP/du; w = handedness, bitangent = w * cross(normal, tangent)
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> triangles;  // counter-clockwise seen from outside

  std::size_t vertexCount() const { return positions.size(); }
};

// Unit sphere at the origin: `latitudes` rings from pole to pole (>= 2), `longitudes` segments around
// (>= 3). The seam and the poles repeat vertices so that the UVs stay continuous; triangles that
// would be degenerate at the poles are left out, so there are 2 * longitudes * (latitudes - 1).
MeshData buildSphereMesh(int latitudes, int longitudes);

// A square of side `size` centred at `centre` in the plane with unit `normal`, facing the normal;
// UVs are in metres (a texture repeats every metre).
MeshData buildPlaneMesh(const glm::vec3& centre, const glm::vec3& normal, float size);

// Faces that meet at more than about 40 degrees show the edge between them (a box's sides); smaller angles
// are shaded smoothly across.
inline constexpr double kHardEdgeCos = 0.766;

// A mesh obstacle as placed in the scene: each corner's normal the area-weighted average of the faces at its
// vertex that meet its face at less than a hard edge's angle (a vertex on a hard edge is drawn once per side),
// any tangent across them, and UVs in metres from its two longest bounding-box axes.
MeshData buildObstacleMesh(const std::vector<glm::dvec3>& positions, const std::vector<std::uint32_t>& triangles);

}  // namespace drape
