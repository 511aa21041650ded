#include "render/cloth_feed.hpp"

#include "gpu/gpu_solver.hpp"

namespace drape {

void computeNormalsAndTangents(const Topology& topology, const std::vector<glm::vec4>& positions,
                               std::vector<glm::vec4>& normals, std::vector<glm::vec4>& tangents) {
  const std::size_t n = positions.size();
  std::vector<glm::vec3> normal(n, glm::vec3(0.0f)), tangent(n, glm::vec3(0.0f)), bitangent(n, glm::vec3(0.0f));
  const auto& tri = topology.triangles;
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3) {
    const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
    const glm::vec3 e1 = glm::vec3(positions[b] - positions[a]), e2 = glm::vec3(positions[c] - positions[a]);
    const glm::vec2 d1 = topology.uvs[b] - topology.uvs[a], d2 = topology.uvs[c] - topology.uvs[a];
    // |cross| is twice the area, so the sum weights each face by its area.
    const glm::vec3 face = glm::cross(e1, e2);
    // dP/du and dP/dv of the triangle from its UV edges (Lengyel 2001); the UV area is the same for
    // every triangle of the grid, so these sums are area-weighted too.
    const float det = d1.x * d2.y - d2.x * d1.y;
    const float r = det != 0.0f ? 1.0f / det : 0.0f;
    const glm::vec3 t_face = (e1 * d2.y - e2 * d1.y) * r, b_face = (e2 * d1.x - e1 * d2.x) * r;
    for (std::uint32_t v : {a, b, c}) {
      normal[v] += face;
      tangent[v] += t_face;
      bitangent[v] += b_face;
    }
  }
  normals.resize(n);
  tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float len = glm::length(normal[i]);
    const glm::vec3 nn = len > 0.0f ? normal[i] / len : glm::vec3(0, 1, 0);
    glm::vec3 t = tangent[i] - glm::dot(tangent[i], nn) * nn;  // Gram-Schmidt against the normal
    const float t_len = glm::length(t);
    t = t_len > 0.0f ? t / t_len : glm::vec3(1, 0, 0);
    const float sign = glm::dot(glm::cross(nn, t), bitangent[i]) < 0.0f ? -1.0f : 1.0f;
    normals[i] = glm::vec4(nn, 0.0f);
    tangents[i] = glm::vec4(t, sign);
  }
}

CpuClothUpload::CpuClothUpload(const Topology& topology)
    : topology_(&topology),
      positions_(gl::Buffer::create(sizeof(glm::vec4) * topology.pointCount())),
      normals_(gl::Buffer::create(sizeof(glm::vec4) * topology.pointCount())),
      tangents_(gl::Buffer::create(sizeof(glm::vec4) * topology.pointCount())) {}

ClothBuffers CpuClothUpload::uploadFrom(Solver& solver) {
  const std::vector<glm::dvec3> x = solver.readPositions();
  positions_cpu_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    positions_cpu_[i] = glm::vec4(glm::vec3(x[i]), 1.0f);
  computeNormalsAndTangents(*topology_, positions_cpu_, normals_cpu_, tangents_cpu_);
  positions_.upload(positions_cpu_);
  normals_.upload(normals_cpu_);
  tangents_.upload(tangents_cpu_);
  return buffers();
}

ClothFeed::ClothFeed(Solver& solver) : solver_(&solver) {
  if (!dynamic_cast<GpuSolver*>(&solver)) upload_ = std::make_unique<CpuClothUpload>(solver.topology());
}

ClothBuffers ClothFeed::prepare() {
  if (upload_) return upload_->uploadFrom(*solver_);
  auto& gpu = static_cast<GpuSolver&>(*solver_);
  gpu.computeNormals();
  return {gpu.positionBuffer().id(), gpu.normalBuffer().id(), gpu.tangentBuffer().id(), gpu.healthBuffer().id()};
}

}  // namespace drape
