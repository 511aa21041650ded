// The cloth's surface as the renderer draws it, from its positions alone (render/cloth_surface.comp on the
// GPU, computeSurface here as its reference).
//
// A grid cell (or a mesh's quad) split along one fixed diagonal cannot show a fold along the other: each
// cell folds along its split instead, and a crease across the diagonals became a row of teeth, in the
// silhouette and in the highlights (the zig-zags along the sphere drape's folds and the flag, which moved to
// the other side of the cloth when the split was flipped). So a quad is drawn as four triangles around a
// centre vertex placed on the diagonal the quad folds along: folding brings the corners on either side of a
// crease closer, so the crease is the diagonal that kept more of its rest length; a flat or evenly bent quad
// gets the average of its corners, and the weight moves smoothly between the two, so nothing pops from frame
// to frame. Point normals sum the faces' normals (a quad's is the cross product of its diagonals: whole
// faces, not the triangles they were split into), and the centre's is weighted like its position.
#pragma once

#include "core/topology.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace drape {

struct SurfaceLayout {
  std::uint32_t points = 0;
  std::uint32_t quads = 0;                  // faces[0, quads) are quads; their centres are vertices points + q
  std::vector<glm::uvec4> faces;            // corners in order around the face; w = kNoCorner for a triangle
  std::vector<std::uint32_t> face_offsets;  // CSR: faces around point i are point_faces[offsets[i], offsets[i+1])
  std::vector<std::uint32_t> point_faces;
  std::vector<glm::vec2> quad_rest;      // per quad: rest lengths of its diagonals (corner 0-2, corner 1-3), m
  std::vector<glm::vec2> uvs;            // per vertex: the points', then the centres' (the corners' average)
  std::vector<std::uint32_t> triangles;  // the element buffer: a quad's four around its centre, then the rest
  std::uint32_t vertices() const { return points + quads; }
};

SurfaceLayout buildSurfaceLayout(const Topology& topology);

// Relative difference of the diagonals' stretch (kept length / rest length) over which the centre moves from
// the corners' average onto the longer-kept diagonal: a square quad folded by about 23 degrees.
inline constexpr float kCreaseBlend = 0.02f;

// The surface pass on the CPU, the reference for the GPU's: for every vertex (points, then centres) its unit
// normal and its unit tangent along +u with the bitangent's sign in w (B = w cross(N, T)), and every centre's
// position (w = 1). A point whose faces have no area keeps +y.
void computeSurface(const SurfaceLayout& layout, const std::vector<glm::vec4>& positions,
                    std::vector<glm::vec4>& normals, std::vector<glm::vec4>& tangents, std::vector<glm::vec4>& centres);

}  // namespace drape
