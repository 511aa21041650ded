// The device's limits as the plan sees them (DeviceLimits, path_choice.hpp), and the check that a scene fits
// them before anything is allocated.
#pragma once

#include "core/scene.hpp"
#include "gpu/gpu_options.hpp"
#include "gpu/path_choice.hpp"
#include "gpu/scene_needs.hpp"

namespace drape::gpu {

// Needs a current context. `max_buffer_bytes`: GpuSolverOptions's (0: the device's own limit).
DeviceLimits queryDeviceLimits(std::size_t max_buffer_bytes, bool software);

// Throws GpuLimitError, naming the sizes involved, when a buffer the scene needs is larger than the device
// allows, or the cloth needs more work groups or binding points than it has. From the scene alone: a cloth too
// large must fail fast, without building gigabytes of springs on the CPU first.
void checkLimits(const Scene& scene, const SceneNeeds& needs, std::uint32_t buckets, const DeviceLimits& device);

}  // namespace drape::gpu
