// The traffic model behind the bench's bytes and GB/s columns: what each planned dispatch's kernel reads and
// writes of the buffers, per cloth point, from their layouts and the cloth's counts; every gather counted as a
// full read (no cache), data every point shares (parameters, colliders) not counted. A substep whose lists are
// fresh (most: the build runs zero work groups) moves no list-build bytes, so none are counted. GL-free.
#pragma once

#include "gpu/path_choice.hpp"

#include <cstdint>

namespace drape::gpu {

struct Plan;
struct Dispatch;

struct TrafficCounts {
  double points = 0;      // the cloth's
  double entries = 0;     // enabled adjacency entries a point (springs seen from both ends)
  double candidates = 0;  // self-collision list entries a point, as the last health read saw them
};

// Bytes a point and substep of the plan's frame: each substep's dispatches, and a share of what runs once a frame.
double bytesPerPointPerSubstep(const Plan& plan, const TrafficCounts& counts);

// The formulas, one per kernel: the kernel table (kernels.cpp) names each pass's.
namespace traffic {
double none(const Plan&, const Dispatch&, const TrafficCounts&);  // no device traffic a substep (see the row)
double forces(const Plan&, const Dispatch&, const TrafficCounts&);
double forcesTiled(const Plan&, const Dispatch&, const TrafficCounts&);
double stretchJacobi(const Plan&, const Dispatch&, const TrafficCounts&);
double stretchColour(const Plan&, const Dispatch&, const TrafficCounts&);
double stretchTiled(const Plan&, const Dispatch&, const TrafficCounts&);
double stretchForcesTiled(const Plan&, const Dispatch&, const TrafficCounts&);
double oneGroup(const Plan&, const Dispatch&, const TrafficCounts&);
double xpbdColour(const Plan&, const Dispatch&, const TrafficCounts&);
double vbdColour(const Plan&, const Dispatch&, const TrafficCounts&);
double collide(const Plan&, const Dispatch&, const TrafficCounts&);
double tether(const Plan&, const Dispatch&, const TrafficCounts&);
double selfCollide(const Plan&, const Dispatch&, const TrafficCounts&);
double collideFaces(const Plan&, const Dispatch&, const TrafficCounts&);
}  // namespace traffic

// A tiled kernel's blocks of `tile` along an edge of `points`, and the points they copy along it with rings of
// `ring` (clipped to the cloth).
std::uint32_t tileCount(int points, std::uint32_t tile);
std::uint64_t copiedPoints(int points, std::uint32_t tile, std::uint32_t ring);
// Points copied into shared memory per cloth point, by blocks of `tile` with rings of `ring` over W x H.
double copiedPerPoint(int W, int H, std::uint32_t tile, std::uint32_t ring);
// The fused kernel's bytes a point of a W x H grid.
double fusedBytesPerPoint(int W, int H, const StretchTiling& tiling);

}  // namespace drape::gpu
