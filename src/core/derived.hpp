// Quantities both solvers, the stability bound and the tools derive from a scene, each written once.
// They return double (or an exact integer); a float solver casts the double, so CPU float and GPU
// start from the same rounded value and stay bit-identical. The model: docs/design.md.
#pragma once

#include "core/scene.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace drape::derived {

// kg per point: the cloth's mass shared equally by its W*H points (CS184).
inline double pointMass(const ClothSpec& cloth) {
  return cloth.width * cloth.height * cloth.density / double(cloth.pointCount());
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

// Buckets of the self-collision hash grid: one per point on average, rounded up to a power of two so
// that a bucket is the hash masked (both solvers build the same grid from this count).
inline std::uint64_t hashBucketCount(std::uint64_t points) {
  return std::bit_ceil(std::max<std::uint64_t>(points, 1));
}

}  // namespace drape::derived

namespace drape {
// Skin of the self-collision candidate lists, in units of the range 2*thickness (chosen by measurement:
// docs/design.md section 6). Both solvers' default.
inline constexpr double kDefaultPairMargin = 0.5;
}  // namespace drape
