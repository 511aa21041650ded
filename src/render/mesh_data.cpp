#include "render/mesh_data.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace drape {

namespace {

constexpr float kPi = 3.14159265358979f;

float handedness(const glm::vec3& normal, const glm::vec3& tangent, const glm::vec3& bitangent) {
  return glm::dot(glm::cross(normal, tangent), bitangent) < 0.0f ? -1.0f : 1.0f;
}

}  // namespace

MeshData buildSphereMesh(int latitudes, int longitudes) {
  if (latitudes < 2 || longitudes < 3)
    throw std::invalid_argument("sphere tessellation needs at least 2 latitudes and 3 longitudes, got " +
                                std::to_string(latitudes) + " and " + std::to_string(longitudes));
  MeshData mesh;
  for (int i = 0; i <= latitudes; ++i) {
    const float theta = kPi * float(i) / float(latitudes);  // from the north pole (+y)
    for (int j = 0; j <= longitudes; ++j) {
      const float phi = 2.0f * kPi * float(j) / float(longitudes);
      const glm::vec3 p{std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)};
      const glm::vec3 tangent{std::cos(phi), 0.0f, -std::sin(phi)};  // d/dphi, defined at the poles too
      const glm::vec3 bitangent{std::cos(theta) * std::sin(phi), -std::sin(theta), std::cos(theta) * std::cos(phi)};
      mesh.positions.emplace_back(p, 1.0f);
      mesh.normals.emplace_back(p, 0.0f);
      mesh.tangents.emplace_back(tangent, handedness(p, tangent, bitangent));
      mesh.uvs.emplace_back(float(j) / float(longitudes), float(i) / float(latitudes));
    }
  }
  const auto index = [&](int i, int j) { return std::uint32_t(i * (longitudes + 1) + j); };
  for (int i = 0; i < latitudes; ++i) {
    for (int j = 0; j < longitudes; ++j) {
      const std::uint32_t a = index(i, j), b = index(i + 1, j), c = index(i, j + 1), d = index(i + 1, j + 1);
      if (i > 0) mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
      if (i < latitudes - 1) mesh.triangles.insert(mesh.triangles.end(), {c, b, d});
    }
  }
  return mesh;
}

MeshData buildObstacleMesh(const std::vector<glm::dvec3>& positions, const std::vector<std::uint32_t>& triangles) {
  const std::size_t face_count = triangles.size() / 3;
  std::vector<glm::dvec3> face(face_count), unit(face_count);
  std::vector<std::vector<std::uint32_t>> around(positions.size());  // the faces at each vertex
  for (std::size_t t = 0; t < face_count; ++t) {
    const glm::dvec3& a = positions[triangles[3 * t]];
    face[t] = glm::cross(positions[triangles[3 * t + 1]] - a, positions[triangles[3 * t + 2]] - a);
    const double len = glm::length(face[t]);
    unit[t] = len > 0.0 ? face[t] / len : glm::dvec3(0.0);
    for (int k = 0; k < 3; ++k)
      around[triangles[3 * t + std::size_t(k)]].push_back(std::uint32_t(t));
  }
  glm::dvec3 lo = positions.front(), hi = lo;
  for (const glm::dvec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 extent = hi - lo;
  const int u = extent.x >= extent.z ? 0 : 2, v = extent.y >= extent[2 - u] ? 1 : 2 - u;

  MeshData m;
  // A corner's normal is the area-weighted sum over the faces at its vertex that meet its own face at less
  // than kHardEdgeCos: a box keeps its flat sides and sharp edges, a curved surface stays smooth. Corners of
  // a vertex with the same normal share one drawn vertex.
  std::vector<std::vector<std::uint32_t>> drawn(positions.size());
  for (std::size_t t = 0; t < face_count; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = triangles[3 * t + std::size_t(k)];
      glm::dvec3 sum(0.0);
      for (std::uint32_t other : around[p])
        if (glm::dot(unit[t], unit[other]) >= kHardEdgeCos) sum += face[other];
      const double len = glm::length(sum);
      const glm::vec3 n = len > 0.0 ? glm::vec3(sum / len) : glm::vec3(0, 1, 0);
      std::uint32_t index = std::uint32_t(m.positions.size());
      for (std::uint32_t candidate : drawn[p])
        if (glm::dot(glm::vec3(m.normals[candidate]), n) > 0.99999f) index = candidate;
      if (index == m.positions.size()) {
        const glm::vec3 tangent =
            glm::normalize(glm::cross(std::fabs(n.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0), n));
        m.positions.emplace_back(glm::vec3(positions[p]), 1.0f);
        m.normals.emplace_back(n, 0.0f);
        m.tangents.emplace_back(tangent, 1.0f);
        m.uvs.emplace_back(float(positions[p][u]), float(positions[p][v]));
        drawn[p].push_back(index);
      }
      m.triangles.push_back(index);
    }
  return m;
}

MeshData buildPlaneMesh(const glm::vec3& centre, const glm::vec3& normal, float size) {
  const glm::vec3 n = glm::normalize(normal);
  // Any direction not parallel to n gives the tangent; prefer x so a ground plane's u runs along x.
  const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  const glm::vec3 tangent = glm::normalize(helper - glm::dot(helper, n) * n);
  const glm::vec3 bitangent = glm::cross(n, tangent);
  MeshData mesh;
  const float half = 0.5f * size;
  for (int corner = 0; corner < 4; ++corner) {
    const float u = (corner & 1) ? half : -half;
    const float v = (corner & 2) ? half : -half;
    mesh.positions.emplace_back(centre + u * tangent + v * bitangent, 1.0f);
    mesh.normals.emplace_back(n, 0.0f);
    mesh.tangents.emplace_back(tangent, 1.0f);
    mesh.uvs.emplace_back(u, v);
  }
  // cross(tangent, bitangent) = n, so (0, 1, 2) is counter-clockwise seen from the normal's side.
  mesh.triangles = {0, 1, 2, 2, 1, 3};
  return mesh;
}

}  // namespace drape
