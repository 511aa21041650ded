// Runs glsl/sim/physics.glsl's collidePlane on one case per invocation, for comparison with the C++
// twin in src/cpu/physics.hpp. Per case, in: x (xyz, w friction), v (xyz), plane point (xyz), plane
// normal (xyz); out: the correction (xyz, w = 1 if it collided).
#include "sim/physics.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Cases {
  vec4 cases[];
};
layout(std430, binding = 1) writeonly buffer Results {
  vec4 results[];
};

uniform uint count;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  vec4 x = cases[4u * i];
  vec3 c;
  bool hit = collidePlane(x.xyz, cases[4u * i + 1u].xyz, cases[4u * i + 2u].xyz, cases[4u * i + 3u].xyz, x.w, c);
  results[i] = vec4(c, hit ? 1.0 : 0.0);
}
