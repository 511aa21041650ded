// The sharp convex features of a mesh obstacle, and the cloth's edges and triangles that meet them. The
// distance field rounds a sharp edge off (it is trilinear between samples 1/128 of the mesh apart) and the
// cloth's points collide with the field only: a cloth triangle draped over a box's edge has its corners on
// both faces and the edge through its middle. collideFaces (physics::edgeContact, cornerContact in
// src/cpu/mesh_physics.hpp) keeps the cloth's edges and triangles the obstacle's collision thickness off
// these features. What each pass reads, in what order: docs/contact.md.
#pragma once

#include "core/mesh_obstacle.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"

#include <cstdint>
#include <vector>

namespace drape {

// An edge is a feature where its two faces' outward normals are more than this apart and it is convex (the
// far corner of each face lies below the other's plane). Smoothly tessellated surfaces stay below it (the
// mannequin's 15 degrees, the torus's 13): there a flat cloth triangle cuts in by at most a tenth of its
// size times the angle, and the field serves. The table's rounded rim (22.5 degrees an edge) and a box's
// edges are above it.
inline constexpr double kFeatureAngleDegrees = 20.0;

struct FeatureEdge {
  glm::dvec3 a{0.0}, b{0.0};
  glm::dvec3 normal_a{0.0}, normal_b{0.0};  // the two faces' outward unit normals
};

struct FeatureCorner {
  glm::dvec3 p{0.0};
  glm::dvec3 normal{0.0};  // outward: the angle-weighted mean of its faces' normals (Baerentzen, Aanaes 2005), unit
};

struct MeshFeatures {
  std::vector<FeatureEdge> edges;
  std::vector<FeatureCorner> corners;  // every end of a feature edge, once
};

MeshFeatures findFeatures(const MeshObstacle& mesh, double min_angle_degrees = kFeatureAngleDegrees);

// The features of `mesh` the face contacts use: findFeatures' less those flush with one of the scene's plane
// colliders (both ends within 1 mm of it, their outer side through it: a box's base on the floor), which the
// cloth cannot pass on that side and where pushing it would fight the plane. Both solvers take these.
MeshFeatures contactFeatures(const Scene& scene, const MeshSpec& mesh);

// The face contacts' grid reach for a mesh of collision thickness `thickness` (m): a cloth edge or triangle
// finds every feature within `thickness` of any of its points from the grid cell of its middle while its
// points are within the longest side at rest of the middle (an edge stretched to twice that, a triangle's
// corners to about 1.9 times their distance from its centroid at rest).
struct FaceAdjacency;
double featureReach(double thickness, const FaceAdjacency& faces);

// The features near each cell of a uniform grid, for a lookup by one cell: cell c lists every feature
// within `reach` of its box, in ascending index, so a cloth edge or triangle whose middle lies in c finds
// every feature within reach of its middle. Cells of edge `reach` (doubled until there are at most
// kMaxFeatureCells), over the features' box grown by reach; a
// point beyond the grid has no feature within reach. Both solvers read the float constants.
struct FeatureGrid {
  glm::dvec3 origin{0.0};
  double cell = 0.0;
  glm::ivec3 dims{0};
  glm::vec3 origin_f{0.0f};
  float inv_cell_f = 0.0f;
  std::vector<std::uint32_t> edge_start, edges;      // CSR over the cells: indices into MeshFeatures::edges
  std::vector<std::uint32_t> corner_start, corners;  // the same for corners
  std::size_t index(glm::ivec3 c) const {
    return (std::size_t(c.z) * std::size_t(dims.y) + std::size_t(c.y)) * std::size_t(dims.x) + std::size_t(c.x);
  }
};

// The most cells a feature grid has (each a uint32 start for edges and one for corners, on the GPU too).
inline constexpr double kMaxFeatureCells = double(1 << 21);

FeatureGrid buildFeatureGrid(const MeshFeatures& features, double reach);

// The cloth's triangle edges and, per point, the edges and triangles it is a corner of (CSR, ascending), the
// order in which a point gathers its face contacts.
struct FaceAdjacency {
  std::vector<std::uint32_t> edges;  // 2 points each, the smaller first, ascending
  std::vector<std::uint32_t> edge_start, point_edges;
  std::vector<std::uint32_t> triangle_start, point_triangles;
  double longest_rest_edge = 0.0;  // m
};

FaceAdjacency buildFaceAdjacency(const Topology& topology);

}  // namespace drape
