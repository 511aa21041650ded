// Long-range attachments (Kim, Tsai and Mueller 2012): each free point is tied to its nearest pinned
// points by a one-sided constraint, |x - x_anchor| <= stretch_limit * rest, rest being the point's distance
// to the anchor along the cloth at rest. A pass of the substep projects every point onto these spheres,
// so a cloth hanging from pins can never be further from them than the stretch limit allows, whatever the
// resolution: the springs and the local stretch limit carry the load one neighbour per sweep, which at
// 1024 x 1024 points and 30 substeps is 2.6 m/s, a speed the falling cloth soon nears. No GL here.
#pragma once

#include "core/topology.hpp"

#include <cstdint>
#include <vector>

namespace drape {

inline constexpr int kMaxTethers = 4;                     // anchors per point at most
inline constexpr std::uint32_t kNoAnchor = 0xffffffffu;   // an unused slot
inline constexpr const char* kTetherPassName = "tether";  // the pass, on every solver

struct Tethers {
  int slots = 0;                      // anchors per point: min(kMaxTethers, pins); 0 for a cloth without pins
  std::vector<std::uint32_t> anchor;  // point i's slot s at i * slots + s, nearest first; kNoAnchor if unused
  std::vector<double> rest;           // m, the rest distance to that anchor (0 in an unused slot)
};

// Anchors are each point's `slots` nearest pins along the springs (a Dijkstra search from all pins at once
// that settles a point once per pin, up to `slots` pins; on a grid with no more pins than slots, simply
// every pin), ordered by rest distance, then index. The rest distance is the straight distance in
// the rest shape for a grid, which is flat and convex, so that is the distance along the cloth; for a mesh
// it is the length of that shortest spring path, which is never shorter than the distance along the
// surface, so a tether never holds a mesh tighter than its rest shape. A pinned point has no tethers.
Tethers buildTethers(const Topology& topo);

}  // namespace drape
