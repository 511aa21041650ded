#include "gpu/colliders.hpp"

#include "core/mesh_obstacle.hpp"
#include "cpu/mesh_physics.hpp"

#include <stdexcept>

namespace drape::gpu {

namespace {

// Two headers per mesh (the second: where its samples start, the offset the cloth keeps from it) after the spheres and
// planes already in `colliders`, then every mesh's samples.
void appendMeshColliders(std::vector<Collider>& colliders, const Scene& scene) {
  const std::vector<MeshSpec>& meshes = scene.meshes;
  const std::size_t headers = colliders.size();
  std::size_t base = headers + 2 * meshes.size();
  for (const MeshSpec& m : meshes) {
    const DistanceField& f = m.mesh->field;
    // Indices travel as floats: exact below 2^24 Colliders, i.e. 128 M samples.
    if (base >= (std::size_t(1) << 24))
      throw std::length_error("mesh obstacles: too many distance samples for the GPU");
    colliders.push_back({glm::vec4(f.origin_f, f.inv_cell_f), glm::vec4(glm::vec3(f.dims), float(m.friction))});
    // The offset as the CPU float solver has it: the thickness rounded to float, then its floor.
    const float offset = physics::meshOffset(float(meshThickness(scene.cloth, m)));
    colliders.push_back({glm::vec4(float(base), offset, 0, 0), glm::vec4(0)});
    base += (f.samples.size() + 7) / 8;
  }
  for (const MeshSpec& m : meshes) {
    const std::vector<float>& s = m.mesh->field.samples;
    for (std::size_t k = 0; k < s.size(); k += 8) {
      float eight[8] = {};
      for (std::size_t j = 0; j < 8 && k + j < s.size(); ++j)
        eight[j] = s[k + j];
      colliders.push_back(
          {glm::vec4(eight[0], eight[1], eight[2], eight[3]), glm::vec4(eight[4], eight[5], eight[6], eight[7])});
    }
  }
}

}  // namespace

std::vector<Collider> colliders(const Scene& scene) {
  std::vector<Collider> out;
  for (const SphereSpec& s : scene.spheres)
    out.push_back({glm::vec4(glm::vec3(s.origin), float(s.radius)), glm::vec4(float(s.friction), 0, 0, 0)});
  for (const PlaneSpec& p : scene.planes)
    out.push_back({glm::vec4(glm::vec3(p.point), float(p.friction)), glm::vec4(glm::vec3(p.normal), 0)});
  appendMeshColliders(out, scene);
  return out;
}

std::uint64_t colliderCount(const Scene& scene) {
  std::uint64_t n = scene.spheres.size() + scene.planes.size() + 2 * scene.meshes.size();
  for (const MeshSpec& m : scene.meshes)
    n += (m.mesh->field.samples.size() + 7) / 8;
  return n;
}

}  // namespace drape::gpu
