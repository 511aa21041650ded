#include "gpu/traffic.hpp"

#include "gpu/kernels.hpp"
#include "gpu/layout.hpp"
#include "gpu/plan.hpp"

#include <algorithm>

namespace drape::gpu {

namespace {

// The state a point, as the buffers lay it out.
constexpr double kPosition = sizeof(glm::vec4);      // w: the pin flag
constexpr double kDisplacement = sizeof(glm::vec3);  // packed
constexpr double kState = kPosition + kDisplacement;
// A point's range in a CSR list (offsets, list starts).
constexpr double kRange = 2 * sizeof(std::uint32_t);

}  // namespace

// Bytes loaded and stored: a gather as often as it is issued; a tiled kernel's copy once per work group (a ring
// copied by two groups twice), and what the group reads again of what it copied not at all.
namespace traffic {

// pairs_prepare: one invocation; the list build: zero work groups while the lists are fresh; the health check and
// picking: once a frame or on request, not a substep's.
double none(const Plan&, const Dispatch&, const TrafficCounts&) {
  return 0;
}

// Own state and point data, the adjacency, each neighbour's position; new state. A grid's weight comes from the
// parameters; the point data only for wind (normal stencil, drag).
double forces(const Plan& p, const Dispatch&, const TrafficCounts& c) {
  const double point = p.needs.grid && !p.needs.wind ? 0 : sizeof(PointMass);
  return kState + point + kRange + c.entries * (sizeof(Neighbor) + sizeof(glm::vec4)) + kState;
}

// Every copied point's position; a block point's displacement; new state.
double forcesTiled(const Plan& p, const Dispatch&, const TrafficCounts&) {
  return copiedPerPoint(p.width, p.height, p.path.tiling.forces_tile, 2) * kPosition + kDisplacement + kState;
}

// The same gather as the forces (each neighbour's pin flag rides in its position's w).
double stretchJacobi(const Plan&, const Dispatch&, const TrafficCounts& c) {
  return kState + kRange + c.entries * (sizeof(Neighbor) + sizeof(glm::vec4)) + kState;
}

// Per spring: the entry, both ends' state read and written.
double stretchColour(const Plan&, const Dispatch& d, const TrafficCounts& c) {
  return double(d.count) * (sizeof(ColouredSpring) + 4 * kState) / c.points;
}

// Every copied point's position and, per colour and pass, its table entry (none where the grid gives partners
// and rests); a block point's displacement; the block's new state.
double stretchTiled(const Plan& p, const Dispatch&, const TrafficCounts&) {
  const double copied = copiedPerPoint(p.width, p.height, p.path.tiling.tile, p.path.tiling.halo);
  const double table =
      p.path.grid_rests.empty() ? double(p.needs.stretch_passes) * p.colours * sizeof(ColourPartner) : 0.0;
  return copied * (kPosition + table) + kDisplacement + kState;
}

double stretchForcesTiled(const Plan& p, const Dispatch&, const TrafficCounts&) {
  return fusedBytesPerPoint(p.width, p.height, p.path.tiling);
}

// Per substep: the adjacency, the stretch table; the state once per frame. Positions are gathered from shared
// memory, not device memory; self-collision's grid lives there too. The state (and the weight, kept in
// registers) is read and written once per dispatch, a frame of steps_per_frame substeps. A flat grid's springs
// come from the grid (GRID_SPRINGS): no adjacency, no table.
double oneGroup(const Plan& p, const Dispatch&, const TrafficCounts& c) {
  const bool grid = !p.path.grid_rests.empty();
  const double frame = kState + sizeof(glm::vec4) + kState;
  double substep = grid ? 0 : kRange + c.entries * sizeof(Neighbor);
  if (p.needs.wind) substep += sizeof(PointMass);
  const bool coloured = p.needs.gauss_seidel;
  const double stretch = !coloured ? kRange + c.entries * sizeof(Neighbor)
                         : grid    ? 0
                                   : p.colours * sizeof(ColourPartner);
  const double tethers = p.tether_slots > 0 ? p.tether_slots * sizeof(Tether) : 0;  // anchors: shared memory
  return frame / p.needs.steps_per_frame + substep + tethers + p.needs.stretch_passes * stretch;
}

// Per spring: the entry, both ends' state and inverse mass read, state written (and the multiplier).
double xpbdColour(const Plan& p, const Dispatch& d, const TrafficCounts& c) {
  return double(d.count) *
         (sizeof(ColouredSpring) + 4 * kState + 2 * sizeof(PointMass) + (p.needs.sweep_state ? 2 * sizeof(float) : 0)) /
         c.points;
}

// Per point of the colour: its index, state, weight, adjacency, neighbours; state written.
double vbdColour(const Plan& p, const Dispatch& d, const TrafficCounts& c) {
  const double weight = p.needs.grid ? 0 : sizeof(PointMass);
  const double inertia = p.needs.sweep_state ? sizeof(glm::vec4) : 0;  // y written, or read
  return double(d.count) *
         (sizeof(std::uint32_t) + 2 * kState + weight + inertia + kRange +
          c.entries * (sizeof(Neighbor) + sizeof(glm::vec4))) /
         c.points;
}

// Own state read and written.
double collide(const Plan&, const Dispatch&, const TrafficCounts&) {
  return 2 * kState;
}

// Own state, each slot's entry and anchor position; own state written.
double tether(const Plan& p, const Dispatch&, const TrafficCounts&) {
  return kState + p.tether_slots * (sizeof(Tether) + sizeof(glm::vec4)) + kState;
}

// Own state, the list, each candidate's position; new state.
double selfCollide(const Plan&, const Dispatch&, const TrafficCounts& c) {
  return kState + kRange + c.candidates * (sizeof(std::uint32_t) + sizeof(glm::vec4)) + kState;
}

// Own state; each of its edges' and triangles' points (about 6 edges and 6 triangles a point on a grid: 6 + 18
// positions) with their indices and the lists (2 + 3 per edge and triangle, a word each); the feature lists of
// the cells they fall in are not counted (empty away from a feature). Own state written.
double collideFaces(const Plan& p, const Dispatch&, const TrafficCounts&) {
  const double meshes = double(p.needs.meshes);
  return kState +
         meshes * ((6 * 2 + 6 * 3) * (sizeof(glm::vec4) + sizeof(std::uint32_t)) + 12 * sizeof(std::uint32_t)) + kState;
}

}  // namespace traffic

double bytesPerPointPerSubstep(const Plan& plan, const TrafficCounts& counts) {
  double substep = 0, tail = 0;
  for (const Dispatch& d : plan.frame.substep)
    substep += kernelRow(d.pass).bytes(plan, d, counts);
  for (const Dispatch& d : plan.frame.tail)
    tail += kernelRow(d.pass).bytes(plan, d, counts);
  return substep + tail / plan.needs.steps_per_frame;
}

std::uint32_t tileCount(int points, std::uint32_t tile) {
  return (std::uint32_t(points) + tile - 1) / tile;
}

// Blocks along one edge, each with its ring clipped to the cloth: the rows (or columns) of points copied.
std::uint64_t copiedPoints(int points, std::uint32_t tile, std::uint32_t ring) {
  std::uint64_t total = 0;
  for (std::uint32_t b = 0; b < tileCount(points, tile); ++b) {
    const std::int64_t lo = std::int64_t(b) * tile, hi = std::min<std::int64_t>(lo + tile, points);
    total += std::uint64_t(std::min<std::int64_t>(hi + ring, points) - std::max<std::int64_t>(lo - ring, 0));
  }
  return total;
}

double copiedPerPoint(int W, int H, std::uint32_t tile, std::uint32_t ring) {
  return double(copiedPoints(W, tile, ring)) * double(copiedPoints(H, tile, ring)) / (double(W) * double(H));
}

// Every copied point's position (a ring of the reach + 2); a block point's displacement; the new state.
double fusedBytesPerPoint(int W, int H, const StretchTiling& tiling) {
  return copiedPerPoint(W, H, tiling.fused_tile, tiling.halo + 2) * kPosition + kDisplacement + kState;
}

}  // namespace drape::gpu
