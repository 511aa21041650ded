// Mesh obstacles' distance fields in the GPU's collider buffer (read by glsl/sim/phases/mesh_collide.glsl).
#pragma once

#include "core/scene.hpp"
#include "gpu/layout.hpp"

#include <vector>

namespace drape {

// Appends, after the spheres and planes already in `colliders`, two headers per mesh and then every
// mesh's samples, 8 floats per Collider. The constants are the floats the CPU reference computes
// (DistanceField::origin_f, inv_cell_f), so both interpolate the same numbers.
void appendMeshColliders(std::vector<gpu::Collider>& colliders, const std::vector<MeshSpec>& meshes);

// Collider entries the scene needs: spheres, planes, and the meshes' headers and samples.
std::uint64_t colliderCount(const Scene& scene);

}  // namespace drape
