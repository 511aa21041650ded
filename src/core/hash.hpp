// 32-bit integer hashing shared by topology (seeded offsets), noise and the self-collision grid. The
// same unsigned arithmetic runs in GLSL (glsl/sim/physics.glsl), so both sides hash identically.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace drape {

// A well-mixed 32-bit integer hash (xorshift-multiply; constants chosen for low bias).
inline std::uint32_t hashU32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

inline std::uint32_t hashCell(glm::ivec3 cell) {
  return hashU32(std::uint32_t(cell.x) + hashU32(std::uint32_t(cell.y) + hashU32(std::uint32_t(cell.z))));
}

}  // namespace drape
