// How far the cloth reaches in the default view's framing directions (ViewReach, render/camera.hpp): with
// x, y, z a point's coordinates along the view's right, up and back from u_origin, the largest -p, p (its
// box), z + x / t_x, z - x / t_x, z + y / t_y, z - y / t_y, z, x and -x over the points. Each work group
// reduces its points in shared memory; the groups meet in atomicMax on uints that order as the floats do.
// A cloth whose health flags are raised is not measured (the renderer hides it), nor a point that is not
// finite or lies beyond the health check's sane bound.
#include "render_bindings.h"

layout(local_size_x = RENDER_REACH_LOCAL_SIZE) in;

layout(std430, binding = RENDER_BINDING_POSITIONS) readonly buffer Positions {
  vec4 positions[];
};
layout(std430, binding = RENDER_BINDING_HEALTH) readonly buffer Health {
  uint health_flags;
};
layout(std430, binding = RENDER_BINDING_REACH) buffer Reach {
  uint reach[RENDER_REACH_VALUES];
};

uniform uint u_point_count;
uniform vec3 u_origin;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec3 u_back;
uniform vec2 u_slopes;  // t_x, t_y

const float kSaneBound = 1e5;  // m, kSaneBound (core/health.hpp)

shared float partial[RENDER_REACH_VALUES][RENDER_REACH_LOCAL_SIZE];

// Sign-magnitude floats to uints that order the same way: a positive float's bits above every negative's.
uint orderedBits(float f) {
  uint u = floatBitsToUint(f);
  return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

void main() {
  if (health_flags != 0u) return;
  uint lane = gl_LocalInvocationID.x;
  float most[RENDER_REACH_VALUES];
  for (int k = 0; k < RENDER_REACH_VALUES; ++k)
    most[k] = uintBitsToFloat(0xff800000u);  // -inf
  uint stride = gl_NumWorkGroups.x * RENDER_REACH_LOCAL_SIZE;
  for (uint i = gl_GlobalInvocationID.x; i < u_point_count; i += stride) {
    vec3 p = positions[i].xyz;
    if (any(isnan(p)) || any(isinf(p)) || any(greaterThan(abs(p), vec3(kSaneBound)))) continue;
    vec3 v = p - u_origin;
    float x = dot(v, u_right), y = dot(v, u_up), z = dot(v, u_back);
    float values[RENDER_REACH_VALUES] = float[](-p.x, -p.y, -p.z, p.x, p.y, p.z, z + x / u_slopes.x, z - x / u_slopes.x,
                                                z + y / u_slopes.y, z - y / u_slopes.y, z, x, -x);
    for (int k = 0; k < RENDER_REACH_VALUES; ++k)
      most[k] = max(most[k], values[k]);
  }
  for (int k = 0; k < RENDER_REACH_VALUES; ++k)
    partial[k][lane] = most[k];
  barrier();
  for (uint half_size = RENDER_REACH_LOCAL_SIZE / 2u; half_size > 0u; half_size /= 2u) {
    if (lane < half_size)
      for (int k = 0; k < RENDER_REACH_VALUES; ++k)
        partial[k][lane] = max(partial[k][lane], partial[k][lane + half_size]);
    barrier();
  }
  // A group that saw no point offers -inf, which orders above the cleared 0 but reads as an empty box.
  if (lane < uint(RENDER_REACH_VALUES)) atomicMax(reach[lane], orderedBits(partial[lane][0]));
}
