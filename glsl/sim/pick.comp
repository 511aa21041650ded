// Ray picking for mouse dragging, in two stages (PICK_STAGE) because GL 4.5 has no 64-bit atomics:
//   0  the smallest ray parameter t >= 0 among points within u_radius of the ray (atomicMin on the
//      float bits, which order like the floats for t >= 0);
//   1  the smallest index among points at exactly that t (the same arithmetic, so the same bits).
#include "common.glsl"

#ifndef PICK_STAGE
#define PICK_STAGE 0
#endif

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kBindingPick) buffer PickBuffer {
  PickResult pick;
};

uniform vec3 u_origin;     // m
uniform vec3 u_direction;  // unit
uniform float u_radius;    // m

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 p = posIn[i].xyz - u_origin;
  float t = dot(p, u_direction);
  vec3 off = p - t * u_direction;
  if (t < 0.0 || dot(off, off) > u_radius * u_radius) return;
#if PICK_STAGE == 0
  atomicMin(pick.best_t_bits, floatBitsToUint(t));
#else
  if (floatBitsToUint(t) == pick.best_t_bits) atomicMin(pick.index, i);
#endif
}
