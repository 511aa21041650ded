#include "core/obj_reader.hpp"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace drape {
namespace {

// tinyobjloader turns an unparsable coordinate into 0 without a word, so every "v" line is read here
// first, strictly: each coordinate must be a finite number.
void checkVertexLines(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  for (long long number = 1; std::getline(lines, line); ++number) {
    std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line.compare(start, 2, "v ") != 0) continue;
    std::istringstream words(line.substr(start + 2));
    std::string word;
    int count = 0;
    while (words >> word && count < 3) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0')
        throw MeshError("line " + std::to_string(number) + ": vertex coordinate '" + word + "' is not a number");
      if (!std::isfinite(v))
        throw MeshError("line " + std::to_string(number) + ": vertex coordinate '" + word + "' is not a finite number");
      ++count;
    }
    if (count < 3) throw MeshError("line " + std::to_string(number) + ": a vertex needs x, y and z");
  }
}

}  // namespace

PolygonMesh parseObj(const std::string& text, long long max_vertices) {
  checkVertexLines(text);
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // quads carry shearing springs; the cloth splits them itself
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, "", config)) {
    std::string error = reader.Error();
    while (!error.empty() && (error.back() == '\n' || error.back() == ' '))
      error.pop_back();
    throw MeshError("cannot parse: " + error);
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::size_t vertex_count = attrib.vertices.size() / 3;
  if ((long long)vertex_count > max_vertices)
    throw MeshError(std::to_string(vertex_count) + " vertices, more than the " + std::to_string(max_vertices) +
                    " a cloth may have");
  PolygonMesh mesh;
  mesh.positions.reserve(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i)
    mesh.positions.emplace_back(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
  const std::size_t texcoord_count = attrib.texcoords.size() / 2;
  std::vector<char> has_uv(vertex_count, 0);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t corner = 0;
    for (unsigned char corners : shape.mesh.num_face_vertices) {
      std::vector<std::uint32_t> face;
      for (unsigned k = 0; k < corners; ++k, ++corner) {
        const tinyobj::index_t& index = shape.mesh.indices[corner];
        if (index.vertex_index < 0 || std::size_t(index.vertex_index) >= vertex_count)
          throw MeshError("face " + std::to_string(mesh.faces.size()) + " names vertex " +
                          std::to_string(index.vertex_index) + ", but the file has " + std::to_string(vertex_count) +
                          " (0 to " + std::to_string(vertex_count - 1) + ")");
        const auto v = std::uint32_t(index.vertex_index);
        face.push_back(v);
        if (index.texcoord_index >= 0 && std::size_t(index.texcoord_index) < texcoord_count && !has_uv[v]) {
          if (mesh.uvs.empty()) mesh.uvs.assign(vertex_count, glm::vec2(0.0f));
          const auto t = std::size_t(index.texcoord_index);
          mesh.uvs[v] = glm::vec2(float(attrib.texcoords[2 * t]), float(attrib.texcoords[2 * t + 1]));
          has_uv[v] = 1;
        }
      }
      mesh.faces.push_back(std::move(face));
    }
  }
  if (mesh.faces.empty()) throw MeshError("no faces (a mesh needs at least one 'f' line)");
  return mesh;
}

void checkFloatRange(const std::vector<glm::dvec3>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::dvec3& p = positions[i];
    if (!(std::fabs(p.x) <= double(FLT_MAX) && std::fabs(p.y) <= double(FLT_MAX) && std::fabs(p.z) <= double(FLT_MAX)))
      throw MeshError("vertex " + std::to_string(i) + " is beyond float range (|coordinate| at most " +
                      std::to_string(FLT_MAX) + ")");
  }
}

PolygonMesh readObj(const std::filesystem::path& file, long long max_vertices) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (!std::filesystem::exists(status)) throw MeshError("cannot open: no such file");
  if (std::filesystem::is_directory(status)) throw MeshError("cannot open: is a directory, not a file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw MeshError(std::string("cannot open: ") + std::strerror(errno));
  // In pieces, never past the limit, whatever size the file claims (a FIFO or /dev/zero claims none).
  std::string text;
  std::vector<char> piece(1 << 20);
  while (in.read(piece.data(), std::streamsize(piece.size())) || in.gcount() > 0) {
    text.append(piece.data(), std::size_t(in.gcount()));
    if (text.size() > std::size_t(kMaxObjBytes))
      throw MeshError("too large (more than " + std::to_string(kMaxObjBytes / (1024 * 1024)) + " MiB)");
  }
  if (in.bad()) throw MeshError(std::string("cannot read: ") + std::strerror(errno));
  return parseObj(text, max_vertices);
}

}  // namespace drape
