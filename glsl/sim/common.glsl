// Buffers, scene variant defaults and indexing shared by the simulation kernels. Mesa counts every
// declared storage block against GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS (16 on llvmpipe), used or not,
// so a kernel that needs none of the springs, colliders or health flags defines SIM_NO_SPRINGS,
// SIM_NO_COLLIDERS or SIM_NO_HEALTH before including this file.
#pragma once

#include "shared/layout.h"

// Scene variant, set per scene by the GPU solver (sceneDefines, src/gpu/kernels.cpp). The defaults only let the
// build-time check compile every kernel without the solver's #defines.
#ifndef NUM_SPHERES
#define NUM_SPHERES 0
#endif
#ifndef NUM_PLANES
#define NUM_PLANES 0
#endif
#ifndef SELF_COLLISION
#define SELF_COLLISION 0
#endif
#ifndef WIND
#define WIND 0
#endif
#ifndef NUM_MESHES
#define NUM_MESHES 0
#endif
#ifndef UNIFORM_MASS
#define UNIFORM_MASS 0  // 1: every point weighs SimParams::weight (a grid), so PointMass is read only for wind
#endif
#define COLLIDERS (NUM_SPHERES + NUM_PLANES + NUM_MESHES > 0)

layout(std430, binding = kBindingParams) readonly buffer ParamsBuffer {
  SimParams params;
};
// A kernel that updates the current state in place (limit_stretch_coloured.comp) defines STATE_IN_PLACE
// before including this file; every other kernel only reads *In.
#ifdef STATE_IN_PLACE
#define STATE_IN_ACCESS
#else
#define STATE_IN_ACCESS readonly
#endif
layout(std430, binding = kBindingPosIn) STATE_IN_ACCESS buffer PosInBuffer {
  vec4 posIn[];
};
// Displacements are packed, 12 bytes a point (vec3[] would be padded to 16): the pin flag rides in the
// position's w alone, so the state is 28 bytes a point.
layout(std430, binding = kBindingDispIn) STATE_IN_ACCESS buffer DispInBuffer {
  float dispIn[];
};
layout(std430, binding = kBindingPosOut) writeonly buffer PosOutBuffer {
  vec4 posOut[];
};
layout(std430, binding = kBindingDispOut) writeonly buffer DispOutBuffer {
  float dispOut[];
};

vec3 loadDisp(uint i) {
  return vec3(dispIn[3u * i], dispIn[3u * i + 1u], dispIn[3u * i + 2u]);
}

void storeDisp(uint i, vec3 v) {
  dispOut[3u * i] = v.x;
  dispOut[3u * i + 1u] = v.y;
  dispOut[3u * i + 2u] = v.z;
}

#ifdef STATE_IN_PLACE
void storeDispInPlace(uint i, vec3 v) {
  dispIn[3u * i] = v.x;
  dispIn[3u * i + 1u] = v.y;
  dispIn[3u * i + 2u] = v.z;
}
#endif
#ifndef SIM_NO_SPRINGS
layout(std430, binding = kBindingOffsets) readonly buffer OffsetsBuffer {
  uint offsets[];
};
layout(std430, binding = kBindingNeighbors) readonly buffer NeighborsBuffer {
  Neighbor neighbors[];
};
#endif
#ifndef SIM_NO_COLLIDERS
layout(std430, binding = kBindingColliders) readonly buffer CollidersBuffer {
  Collider colliders[];
};
#endif
#ifndef SIM_NO_HEALTH
layout(std430, binding = kBindingHealth) buffer HealthBuffer {
  Health health;
};
#endif

// 1D index over a 2D dispatch: more than 65535 work groups along x is not guaranteed, so large
// cloths spread their groups over y as well (the solver computes the split). Per-point kernels use
// kLocalSize (gl_WorkGroupSize is not declared yet where this file is included).
uint globalIndex() {
  return gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * kLocalSize) + gl_GlobalInvocationID.x;
}

// The pin flag rides in the position's w (a neighbour's position is all a gather of it needs).
bool isPinned(vec4 position) {
  return position.w != 0.0;
}

uint neighborIndex(Neighbor nb) {
  return nb.index_type & kNeighborIndexMask;
}
uint neighborType(Neighbor nb) {
  return nb.index_type >> kNeighborIndexBits;
}
