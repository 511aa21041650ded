// Wavefront OBJ input, read here line by line with one strict grammar: a vertex coordinate is a decimal
// number and finite (no "nan", "inf", hex or trailing letters, whatever the whitespace around it), a face
// corner is an index that names a vertex already read, and every count is held to its limit while the
// file is read, so that a file too large for its purpose is refused before it costs its memory. Only
// what a cloth or an obstacle uses is kept (positions, faces, texture coordinates); other statements
// (vn, o, g, s, usemtl, mtllib, l, ...) are read past, vn's numbers checked like any other.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
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
// Checked before reading a regular file; a FIFO is read no further.
inline constexpr long long kMaxObjBytes = 512LL * 1024 * 1024;
// One line of an OBJ file: a face of 50,000 corners fits.
inline constexpr std::size_t kMaxObjLineBytes = 1 << 20;

// What one file may hold. Faces and corners follow from the vertices: a closed triangle mesh has about
// 2 faces and 6 corners a vertex, a quad grid 1 and 4.
struct ObjLimits {
  long long vertices = 0;
  std::string vertices_note;  // after "more than N vertices": whose limit it is, e.g. "(a cloth's limit)"
  long long faces() const { return 2 * vertices + 16; }
  long long corners() const { return 6 * vertices + 48; }
};

// Throws MeshError: missing or unreadable file, too large, a statement that breaks the grammar (with its
// line), a face corner out of range, a count beyond `limits`, no faces.
PolygonMesh readObj(const std::filesystem::path& file, const ObjLimits& limits);
PolygonMesh parseObj(std::string_view text, const ObjLimits& limits);

// The solvers compute in float: a vertex beyond float's range would be infinite there. Throws MeshError
// naming the first such vertex.
void checkFloatRange(const std::vector<glm::dvec3>& positions);

}  // namespace drape
