// Quantities both solvers, the stability bound and the tools derive from a scene, each written once.
// They return double (or an exact integer); a float solver casts the double, so CPU float and GPU
// start from the same rounded value and stay bit-identical. The model: docs/design.md.
#pragma once

#include "core/scene.hpp"
#include "core/topology.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace drape::derived {

// kg per point: the cloth's mass shared equally by its W*H points (CS184).
inline double pointMass(const ClothSpec& cloth) {
  return cloth.width * cloth.height * cloth.density / double(cloth.pointCount());
}

// kg of one point: a grid's is the same for all (above, CS184's); a mesh vertex's is its area's.
inline double pointMass(const ClothSpec& cloth, const Topology& topo, std::size_t i) {
  return cloth.isGrid() ? pointMass(cloth) : cloth.density * topo.area[i];
}

// Wind drag times a point's area (kg/m): on a grid the same for all, in the grid's original operation order.
inline double dragArea(double drag, const ClothSpec& cloth, const Topology& topo, std::size_t i) {
  return cloth.isGrid() ? drag * cloth.width * cloth.height / double(cloth.pointCount()) : drag * topo.area[i];
}

// N/m. Bending springs are softer than the others by a fixed factor (CS184: 0.2).
inline constexpr double kBendingFactor = 0.2;
inline double bendingStiffness(const ClothSpec& cloth) {
  return kBendingFactor * cloth.ks;
}

// N/m of one spring of type t, whether or not the type is enabled.
inline double springStiffness(const ClothSpec& cloth, SpringType t) {
  return t == SpringType::Bending ? bendingStiffness(cloth) : cloth.ks;
}

// XPBD's time-scaled compliance of a spring of type t, alpha / dt^2 with alpha = 1/k (s^2 kg^-1 / s^2).
inline double xpbdAlphaTilde(const ClothSpec& cloth, const SimParams& sim, SpringType t) {
  const double dt = sim.dt();
  return 1.0 / (springStiffness(cloth, t) * dt * dt);
}

// Buckets of the self-collision hash grid: one per point on average, rounded up to a power of two so
// that a bucket is the hash masked (both solvers build the same grid from this count).
inline std::uint64_t hashBucketCount(std::uint64_t points) {
  return std::bit_ceil(std::max<std::uint64_t>(points, 1));
}

}  // namespace drape::derived

namespace drape {
// Skin of the self-collision candidate lists, in units of the range 2*thickness (chosen by measurement:
// docs/design.md section 6). Both solvers' default.
inline constexpr double kDefaultPairMargin = 0.75;
}  // namespace drape

namespace drape::derived {
// The lists' skin for a contact distance `range`: `margin` of it, or on a cloth finer than three quarters of
// it, `margin` of 4/3 spacings (the shortest structural spring at rest). There the stencil tests the ring of
// unheld pairs between range and range + skin every substep, so the skin is its depth in lattice spacings:
// one at the default (half a spacing ran pinned2 at 128^2 and 256^2 with CS184's thickness 7% and 13% slower,
// rebuilding twice as often, 1.5 spacings 20% slower, its ring wider; docs/contact.md). In T, as each solver
// computes it.
template <class T>
T pairSkin(double margin, T range, double shortest_spring) {
  return T(margin) * std::min(range, T(4.0 / 3.0) * T(shortest_spring));
}
}  // namespace drape::derived
