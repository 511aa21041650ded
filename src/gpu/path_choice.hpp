// Which of the GPU solver's paths runs a scene, and why the others do not: a GL-free value worked out from
// the scene's needs, its cloth and the device's limits (docs/design.md section 4).
#pragma once

#include "core/colouring.hpp"
#include "core/topology.hpp"
#include "gpu/scene_needs.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace drape {

// How a substep is dispatched. General: a dispatch per pass, any cloth, the Gauss-Seidel stretch limit one
// dispatch per colour. Tiled: the same with the stretch limit's colours and passes in one dispatch of blocks
// in shared memory (glsl/sim/limit_stretch_tiled.comp), for grid cloths whose colouring reaches few enough
// points for a block and its ring to fit. OneDispatch: every substep of a frame in one work group with the
// cloth in shared memory (glsl/sim/one_group.comp), for cloths that fit it. Auto: OneDispatch where it fits on a
// hardware GPU, else General; on a software renderer (llvmpipe) always General, which spreads a frame over its
// threads where one work group runs on one (docs/results/README.md, "GPU paths"). Auto never tiles: on an H200 the
// general path was as fast or faster (docs/results/README.md, "On an NVIDIA H200").
enum class GpuPath { Auto, General, Tiled, OneDispatch };

namespace gpu {

// What the plan needs to know of the device (GpuSolver queries it; tests pass llvmpipe's or NVIDIA's).
struct DeviceLimits {
  std::uint64_t shared_bytes = 32768;         // GL_MAX_COMPUTE_SHARED_MEMORY_SIZE
  std::uint32_t group_invocations = 1024;     // GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS
  std::uint32_t group_size_x = 1024;          // GL_MAX_COMPUTE_WORK_GROUP_SIZE along x
  std::uint32_t max_groups_x = 65535;         // GL_MAX_COMPUTE_WORK_GROUP_COUNT along x
  std::uint32_t max_groups_y = 65535;         // ... along y
  std::uint64_t max_buffer_bytes = 1u << 27;  // GL_MAX_SHADER_STORAGE_BLOCK_SIZE, or GpuSolverOptions::max_buffer_bytes
  bool buffer_limit_is_option = false;        // max_buffer_bytes came from GpuSolverOptions (for messages)
  int storage_bindings = 96;                  // GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
  bool software = false;                      // a software renderer (llvmpipe)

  std::uint32_t largestGroup() const { return group_invocations < group_size_x ? group_invocations : group_size_x; }
};

// The tiled kernels' block edge and ring width in points, and their invocations; all 0 where they do not apply.
struct StretchTiling {
  std::uint32_t tile = 0, halo = 0, group_size = 0;
  std::uint32_t forces_tile = 0, forces_group_size = 0;  // forces_integrate_tiled.comp's (ring 2)
  std::uint32_t fused_tile = 0;  // limit_stretch_forces_tiled.comp's: the same copy, a ring of halo + 2
};

// The tiling for a device with `shared` bytes of shared memory a work group and `max_group` invocations, for a
// colouring that reaches `reach` points.
StretchTiling tilingFor(std::uint64_t shared, std::uint64_t max_group, int reach);

struct PathChoice {
  GpuPath path = GpuPath::General;  // what runs: General, Tiled or OneDispatch
  std::string one_dispatch_misfit;  // why the one-dispatch path does not fit ("" if it does)
  std::string tiled_misfit;         // why the tiled stretch limit does not apply ("not asked for": not worked out)
  // A forced path (GpuPath::Tiled, OneDispatch) that does not fit: the message a new solver throws with. A live
  // parameter change that makes it misfit moves the solver to the general path instead.
  std::string refusal;
  StretchTiling tiling;             // Tiled
  bool tiled_forces = false;        // Tiled: forces_integrate_tiled.comp gathers the springs by grid offset
  bool fused_frame = false;         // Tiled: stepFrame() fuses each stretch limit with the next forces
  std::vector<float> grid_rests;    // Tiled, OneDispatch: each grid direction's one rest length (0: none
                                    // or disabled); empty where a direction's rests differ
  bool colour_partners = false;     // the stretch limit seen from the points reads the ColourPartner table
  std::uint32_t group_size = 0;     // OneDispatch: the kernel's invocations
  std::uint32_t group_buckets = 0;  // OneDispatch: its in-group self-collision grid's buckets
};

// GpuSolverOptions::path for this scene on this device. `tether_pass`: a tether pass runs each substep.
PathChoice choosePath(const SceneNeeds& needs, const Topology& topo, const SpringColouring& colouring, bool tether_pass,
                      GpuPath asked, const DeviceLimits& device);

// Why the one-dispatch path does not fit the scene ("" where it does).
std::string oneDispatchMisfit(const SceneNeeds& needs, std::uint64_t points, const DeviceLimits& device);
// The tiling the scene's colouring allows on this device (zero where the cloth is not a Gauss-Seidel grid).
StretchTiling stretchTiling(const SceneNeeds& needs, const Topology& topo, const SpringColouring& colouring,
                            const DeviceLimits& device);
// Why the tiled stretch limit does not apply ("" where it does), for a worked-out tiling.
std::string tiledMisfit(const SceneNeeds& needs, const StretchTiling& tiling, const DeviceLimits& device);
// Each grid direction's rest length where all its enabled springs share one as a float; empty where they differ.
std::vector<float> uniformGridRests(const Topology& topo, const SceneNeeds& needs);

}  // namespace gpu
}  // namespace drape
