#include "gpu/path_choice.hpp"

#include <algorithm>
#include <bit>

namespace drape::gpu {

namespace {

// Shared memory holds 12 bytes of position per point and a pin bit, and with self-collision the in-group
// grid (a bucket start per bucket, an index per point); registers hold the rest. More than a few points
// per invocation would spill registers, so a cloth needs about as many invocations as points /
// kMaxPointsPerInvocation.
constexpr std::uint32_t kMaxPointsPerInvocation = 8;
// Blocks smaller than this copy too much ring per point they own (with a ring of 10: 12 points each).
constexpr std::uint32_t kMinStretchTile = 8;

std::uint64_t oneGroupSharedBytes(std::uint64_t points, std::uint64_t buckets, bool contacts) {
  const std::uint64_t state = 12 * points + 4 * ((points + 31) / 32);
  return contacts ? state + 4 * (buckets + 1) + 4 * points : state;
}

// As many invocations as points up to the limit, a whole number of 32-wide warps.
std::uint32_t oneGroupSize(std::uint64_t points, const DeviceLimits& device) {
  return std::min<std::uint32_t>(std::uint32_t((points + 31) / 32 * 32), device.largestGroup());
}

// One bucket per invocation for the scan: the largest power of two not above the group size.
std::uint32_t oneGroupBuckets(std::uint64_t points, const DeviceLimits& device) {
  return std::bit_floor(std::max<std::uint32_t>(oneGroupSize(points, device), 1));
}

}  // namespace

std::string oneDispatchMisfit(const SceneNeeds& needs, std::uint64_t n, const DeviceLimits& device) {
  if (needs.predicts)
    return std::string("the ") + integratorName(needs.integrator) +
           " integrator runs on the general path only (one_group.comp has Verlet's phases)";
  if (needs.faces)
    return "the contacts with a mesh's sharp edges and corners run on the general path only (collide_faces.comp)";
  if (needs.held)
    return "self-collision skipping the pairs held at rest runs on the general path only (the in-group grid has no "
           "rest positions)";
  const std::uint64_t need = oneGroupSharedBytes(n, oneGroupBuckets(n, device), needs.contacts);
  if (need > device.shared_bytes)
    return std::to_string(n) + " points need " + std::to_string(need) + " bytes of shared memory" +
           (needs.contacts ? " with self-collision" : "") + ", more than GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (" +
           std::to_string(device.shared_bytes) + ")";
  if (n > std::uint64_t(oneGroupSize(n, device)) * kMaxPointsPerInvocation)
    return std::to_string(n) + " points are more than " + std::to_string(kMaxPointsPerInvocation) +
           " per invocation of the largest work group (" + std::to_string(oneGroupSize(n, device)) + " invocations)";
  return "";
}

// The ring a block copies is the colouring's reach (gridColourReach); the block is the largest that fits
// shared memory with it, at 12 bytes and a pin bit a point, as one_group.comp.
StretchTiling stretchTiling(const SceneNeeds& needs, const Topology& topo, const SpringColouring& colouring,
                            const DeviceLimits& device) {
  if (!needs.grid || !needs.gauss_seidel) return {};
  const int reach = gridColourReach(topo, colouring, needs.stretch_passes, needs.spring_mask);
  return tilingFor(device.shared_bytes, device.largestGroup(), reach);
}

StretchTiling tilingFor(std::uint64_t shared, std::uint64_t max_group, int reach) {
  std::uint64_t region = 0;
  while (true) {
    const std::uint64_t next = region + 1, points = next * next;
    if (12 * points + 4 * ((points + 31) / 32) > shared || points > max_group * kMaxPointsPerInvocation) break;
    region = next;
  }
  StretchTiling t;
  t.halo = std::uint32_t(reach);
  if (region < 2 * std::uint64_t(reach) + kMinStretchTile) return t;
  t.tile = std::uint32_t(region) - 2 * t.halo;
  t.fused_tile = t.tile >= 4 + kMinStretchTile ? t.tile - 4 : 0;
  const std::uint64_t per_group = (region * region + kMaxPointsPerInvocation - 1) / kMaxPointsPerInvocation;
  t.group_size = std::uint32_t(std::min(max_group, (per_group + 31) / 32 * 32));
  // The forces' copy: positions only, a ring of 2; the block's points are the work, 8 an invocation at most.
  std::uint64_t forces_tile = 0;
  const auto forcesFit = [&](std::uint64_t tile) {
    return 12 * (tile + 4) * (tile + 4) <= shared && tile * tile <= max_group * kMaxPointsPerInvocation;
  };
  while (forcesFit(forces_tile + 1))
    ++forces_tile;
  t.forces_tile = std::uint32_t(forces_tile);
  const std::uint64_t forces_points = forces_tile * forces_tile;
  t.forces_group_size = std::uint32_t(
      std::min(max_group, ((forces_points + kMaxPointsPerInvocation - 1) / kMaxPointsPerInvocation + 31) / 32 * 32));
  return t;
}

std::string tiledMisfit(const SceneNeeds& needs, const StretchTiling& t, const DeviceLimits& device) {
  if (!needs.grid) return "the tiled stretch limit needs a grid cloth (a mesh cloth's springs have no blocks)";
  if (!needs.gauss_seidel)
    return "the Jacobi stretch scheme is one dispatch a pass already; the tiled kernel runs the Gauss-Seidel one";
  if (t.tile < kMinStretchTile)
    return std::to_string(needs.stretch_passes) + " stretch passes reach " + std::to_string(t.halo) +
           " points around a block, too many for a block of at least " + std::to_string(kMinStretchTile) +
           " points a side in GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (" + std::to_string(device.shared_bytes) + ")";
  return "";
}

std::vector<float> uniformGridRests(const Topology& topo, const SceneNeeds& needs) {
  std::vector<float> rests(kGridDirectionCount, 0.0f);
  std::vector<bool> seen(kGridDirectionCount, false);
  for (const Spring& s : topo.springs) {
    if (!needs.springs[std::size_t(s.type)]) continue;
    const auto d = std::size_t(gridDirection(topo, s));
    const float rest = float(s.rest);
    if (seen[d] && rest != rests[d]) return {};
    rests[d] = rest;
    seen[d] = true;
  }
  return rests;
}

PathChoice choosePath(const SceneNeeds& needs, const Topology& topo, const SpringColouring& colouring, bool tether_pass,
                      GpuPath asked, const DeviceLimits& device) {
  PathChoice c;
  const std::uint64_t n = std::uint64_t(topo.pointCount());
  c.one_dispatch_misfit = oneDispatchMisfit(needs, n, device);
  if (asked == GpuPath::OneDispatch && !c.one_dispatch_misfit.empty())
    c.refusal = "gpu solver: the one-dispatch path does not fit: " + c.one_dispatch_misfit;
  // The colouring's reach is worked out only where the tiled path may run: it walks every spring once per
  // stretch pass.
  // Only when asked for: on an H200 the tiled stretch limit took 1.2-3.6 times the general path's frame on pinned2
  // from 64² to 512², and was within 13% of it with self-collision (docs/results/README.md, "On an NVIDIA H200").
  const bool may_tile = asked == GpuPath::Tiled;
  const StretchTiling tiling = may_tile ? stretchTiling(needs, topo, colouring, device) : StretchTiling{};
  c.tiled_misfit = may_tile ? tiledMisfit(needs, tiling, device) : "not asked for";
  if (asked == GpuPath::Tiled && !c.tiled_misfit.empty())
    c.refusal = "gpu solver: the tiled stretch limit does not apply: " + c.tiled_misfit;
  // Forced, either still gives way to the general path when a live change (self-collision on, a stretch pass
  // more) makes it misfit.
  const bool one_group =
      c.one_dispatch_misfit.empty() && (asked == GpuPath::OneDispatch || (asked == GpuPath::Auto && !device.software));
  const bool tiled = !one_group && may_tile && c.tiled_misfit.empty();
  c.path = one_group ? GpuPath::OneDispatch : tiled ? GpuPath::Tiled : GpuPath::General;
  if (tiled) c.tiling = tiling;
  if ((tiled || one_group) && needs.grid) c.grid_rests = uniformGridRests(topo, needs);
  // The table serves the Gauss-Seidel stretch seen from the points, where the grid cannot.
  c.colour_partners = (tiled || one_group) && c.grid_rests.empty();
  // The tiled forces kernel sums springs found by grid offset with one rest length per direction, and has no
  // wind; XPBD and VBD predict without springs.
  c.tiled_forces =
      tiled && !c.grid_rests.empty() && !needs.wind && !needs.predicts && c.tiling.forces_tile >= kMinStretchTile;
  // Fused only where nothing runs between a stretch limit and the next forces (neither the tethers nor the
  // collisions again: those would need the ring's displacements); the forces need a ring of 2 stretched points
  // around a block, so the fused copy's ring is 2 wider.
  c.fused_frame = c.tiled_forces && !needs.contacts && !tether_pass && !needs.fusion.collide_last &&
                  needs.stretch_passes > 0 && c.tiling.fused_tile >= kMinStretchTile;
  if (one_group) {
    c.group_size = oneGroupSize(n, device);
    c.group_buckets = oneGroupBuckets(n, device);
  }
  return c;
}

}  // namespace drape::gpu
