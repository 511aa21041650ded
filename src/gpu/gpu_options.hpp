// How a GpuSolver is set up, and the error it throws when a scene does not fit the device.
#pragma once

#include "core/derived.hpp"
#include "core/health.hpp"
#include "gpu/path_choice.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>

namespace drape {

struct GpuSolverOptions {
  GpuPath path = GpuPath::Auto;
  std::uint32_t buckets = 0;         // self-collision hash buckets, a power of two; 0: one per point, as the CPU grid
  bool timing = false;               // time every pass (GL timer queries; else glFinish + wall clock, which stalls)
  HealthLimits health{};             // what health() reports as a blow-up
  std::size_t max_buffer_bytes = 0;  // largest buffer allowed; 0: GL_MAX_SHADER_STORAGE_BLOCK_SIZE
  double pair_margin = kDefaultPairMargin;  // self-collision list skin (derived::pairSkin), as CpuSolverOptions
  std::size_t pair_capacity = 0;            // list entries the buffer holds at first; 0: estimated from the cloth
  // Nonzero terms of a point's self-collision sum kept in registers while its list is swept once; a
  // point with more sums them by sweeping its list again per cell order (same bits, more gathers). -1:
  // chosen per device, 8 on a hardware GPU, 0 on a software renderer, where a gather is a cached load and
  // holding the terms costs more than it saves (docs/results/README.md, "Self-collision on the GPU"). At most 32.
  int self_terms_held = -1;
};

// The scene needs more than the GPU allows (buffer size, work groups, memory). Thrown before any
// dispatch, with the sizes involved.
class GpuLimitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace drape
