// C++ side of glsl/shared/layout.h: the std430 structs and binding points shared with the kernels.
// The header itself includes nothing (the GLSL loader would try to resolve it), so glm and <cstdint>
// come first here.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <type_traits>

#include "shared/layout.h"

namespace drape::gpu {

// std430 puts scalars at 4-byte and vec4 at 16-byte boundaries and rounds a struct with a vec4 to 16
// bytes; glm's vec4 is only 4-byte aligned, so the layouts stay correct only while every struct keeps
// vec4s at multiples of 16 and is padded to a multiple of 16. tests/layout_test.cpp checks offsets.
static_assert(sizeof(SimParams) % 16 == 0 && sizeof(Collider) % 16 == 0 && sizeof(Health) % 16 == 0 &&
              sizeof(PickResult) % 16 == 0);
static_assert(sizeof(Neighbor) == 8 && sizeof(GridPoint) == 20 && sizeof(GridEntry) == 16);
static_assert(std::is_trivially_copyable_v<SimParams> && std::is_standard_layout_v<SimParams>);
static_assert(kScanBlock == kScanLocalSize * kScanItems);

}  // namespace drape::gpu
