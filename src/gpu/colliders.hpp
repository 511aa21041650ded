// The GPU's collider buffer (binding kBindingColliders), built and sized here and nowhere else: the spheres, the
// planes, then two headers per mesh obstacle and every mesh's distance samples, 8 floats per Collider (read by
// glsl/sim/phases/collide.glsl and mesh_collide.glsl). Whether a kernel collides at all, and with how many of
// each, is the plan's decision (SceneNeeds, scene_needs.hpp). GL-free.
#pragma once

#include "core/scene.hpp"
#include "gpu/layout.hpp"

#include <cstdint>
#include <vector>

namespace drape::gpu {

// The buffer's contents. The mesh constants are the floats the CPU reference computes (DistanceField::origin_f,
// inv_cell_f), so both interpolate the same numbers.
std::vector<Collider> colliders(const Scene& scene);

// Its entries, worked out without building it (the device limits check it before anything is allocated).
std::uint64_t colliderCount(const Scene& scene);

}  // namespace drape::gpu
