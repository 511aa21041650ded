// The cloth on the GPU: its state (two copies that ping-pong passes alternate between) and every buffer the
// kernels read, built from the host tables of cloth_tables.hpp; the narrow face the renderer reads (the current
// positions and the health flags: it computes its normals from the positions, render/surface_pass.hpp); and the
// explicit, named reads and writes of points.
#pragma once

#include "core/colouring.hpp"
#include "core/scene.hpp"
#include "core/topology.hpp"
#include "gl/objects.hpp"
#include "gpu/cloth_tables.hpp"
#include "gpu/kernels.hpp"
#include "gpu/plan.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace drape::gpu {

class DeviceCloth {
 public:
  // The state, the per-point buffers, the colliders and the health flags of `topo`, which must outlive it.
  DeviceCloth(const Scene& scene, const Topology& topo);

  void uploadParams(const Scene& scene, const ParamsInput& in);
  // The adjacency and coloured springs of the enabled spring types (again after a change of them).
  void uploadSprings(const SpringColouring& colouring, const SceneNeeds& needs);
  // What the scene's integrator, tethers and self-collision need beyond that, allocated the first time they are
  // asked for; whether some pair is held at rest at the cloth's thickness (checked again on every call).
  void prepareFor(const SceneNeeds& needs, double thickness);
  // The colliders again (the meshes' offset follows the cloth's thickness where they have none of their own).
  void uploadColliders(const Scene& scene);
  // The ColourPartner table, where the plan's stretch limit reads it (kBindColourPartners), else released.
  void setColourPartners(bool needed, const SpringColouring& colouring, const SceneNeeds& needs);
  const ClothCounts& counts() const { return counts_; }

  // The renderer (or anything else) may bind its own buffers to the same indices between our calls, so every
  // stage binds what it uses; a binding is a cheap state change.
  void bindShared() const;
  void bindState() const;                   // the current copy as *In, the other as *Out
  void bind(std::uint16_t bindings) const;  // Binding bits: the buffers of a kernel row that exist
  void swapState() { current_ = 1 - current_; }

  void reset();  // the initial positions, at rest; nothing held
  // Replaces the state (positions, displacements); pin flags stay (a held point stays pinned).
  void uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v);
  std::vector<glm::dvec3> readPositions() const;
  std::vector<glm::dvec3> readDisplacements() const;
  // Mouse dragging: see GpuSolver.
  void setPosition(std::uint32_t index, glm::vec3 position);
  void holdPoint(int index, glm::vec3 target);
  void releasePoint();

  void clearHealth();
  Health readHealth() const;  // waits for the GPU
  void clearPick();           // nothing found yet (PickResult)
  PickResult readPick() const;

  const gl::Buffer& position() const { return state_[current_].position; }
  const gl::Buffer& health() const { return health_; }
  std::size_t bytes() const;

 private:
  void writePoint(std::uint32_t index, const glm::vec4* position, const glm::vec3* displacement);

  struct StateBuffers {
    gl::Buffer position;      // vec4 per point, w = pin flag
    gl::Buffer displacement;  // 3 floats per point, packed (glm::vec3)
  };
  const Topology* topo_;
  StateBuffers state_[2];
  int current_ = 0;
  int held_ = -1;
  gl::Buffer params_, point_mass_, offsets_, neighbors_, colliders_, health_, pick_;
  gl::Buffer coloured_springs_;            // ColouredSpring, enabled springs in colour order
  gl::Buffer xpbd_lambda_;                 // float per coloured spring, XPBD with more than one sweep
  gl::Buffer coloured_points_;             // VBD: point indices grouped by colour (colourPoints)
  gl::Buffer vbd_inertia_;                 // VBD with more than one sweep: vec4 per point, the prediction y
  gl::Buffer colour_partners_;             // ColourPartner table
  gl::Buffer tethers_;                     // Tether per point and slot, once the scene asks for them
  gl::Buffer rest_;                        // 3 floats a point, where self-collision has pairs held at rest
  gl::Buffer face_table_, face_features_;  // the face contacts (face_tables.hpp), where a mesh has sharp features
  double held_thickness_ = -1;             // the thickness counts_.held_pairs was checked at
  ClothCounts counts_;
};

}  // namespace drape::gpu
