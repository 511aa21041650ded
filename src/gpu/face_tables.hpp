// What the face contacts (collide_faces.comp, phases/faces.glsl) read on the GPU, worked out on the host as
// CpuSolver<float>::buildFaceContacts does (the same features, grids and float roundings), in two buffers: the
// FaceTable of uints (the cloth's face adjacency, each mesh's feature grid, their offsets) and the FaceFeatures of
// vec4s (each mesh's grid constants and its features). Their layout: glsl/shared/layout.h, kFace*. GL-free.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace drape::gpu {

struct FaceTables {
  std::vector<std::uint32_t> table;
  std::vector<glm::vec4> features;
  int meshes = 0;  // meshes with a sharp feature; 0: the face contacts do not run, and both vectors are empty
};

FaceTables faceTables(const Scene& scene, const Topology& topo);

}  // namespace drape::gpu
