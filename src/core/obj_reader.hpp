// Wavefront OBJ input through Debian's tinyobjloader, with the checks tinyobjloader leaves out: it reads
// "nan" and "inf" as 0 and keeps going past a face index out of range, which would put a point at the
// origin or read past an array. A mesh that is read is finite and every face corner names a vertex.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

// The problem only ("line 4: ..."); the caller puts the file and the scene key in front.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PolygonMesh {
  std::vector<glm::dvec3> positions;
  std::vector<std::vector<std::uint32_t>> faces;  // vertex indices, as wound in the file
  std::vector<glm::vec2> uvs;                     // per vertex: its first face corner's texcoord; empty without any
};

// OBJ files beyond this are not meshes a cloth or an obstacle here needs (a 2048^2 grid is ~200 MB of text).
inline constexpr long long kMaxObjBytes = 512LL * 1024 * 1024;

// Throws MeshError: missing or unreadable file, a parse error, a non-finite coordinate, a face corner
// out of range, no faces, more than `max_vertices` vertices.
PolygonMesh readObj(const std::filesystem::path& file, long long max_vertices);

// The solvers compute in float: a vertex beyond float's range would be infinite there. Throws MeshError
// naming the first such vertex.
void checkFloatRange(const std::vector<glm::dvec3>& positions);
PolygonMesh parseObj(const std::string& text, long long max_vertices);

}  // namespace drape
