// Collision with a mesh obstacle's signed distance field: collideField of src/cpu/mesh_physics.hpp, the
// same float operations in the same order. The fields ride in the collider buffer after the spheres and
// planes (gpu::colliders, src/gpu/cloth_tables.cpp): two headers per mesh, then the samples of every mesh, 8 per
// Collider. A buffer of their own would be a 17th storage block in the self-collision kernel, one more
// than Mesa allows.
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

float fieldSample(uint base, ivec3 dims, ivec3 i) {
  uint k = uint((i.z * dims.y + i.y) * dims.x + i.x);
  Collider c = colliders[base + (k >> 3u)];
  uint r = k & 7u;
  vec4 q = r < 4u ? c.a : c.b;
  return q[r & 3u];
}

// Mesh m's headers: colliders[first] = (origin, 1 / cell), (dims, friction); colliders[first + 1].a = (the
// index of the Collider holding its sample 0, the offset: physics::meshOffset of the obstacle's thickness).
bool collideField(vec3 x, vec3 v, uint first, out vec3 c) {
  c = vec3(0.0);
  Collider h0 = colliders[first];
  vec4 h1 = colliders[first + 1u].a;
  uint base = uint(h1.x);
  float offset = h1.y;
  ivec3 dims = ivec3(h0.b.xyz);
  precise vec3 g = (x - h0.a.xyz) * h0.a.w;
  // isnan spelled out: a compiler may assume no NaN and fold the range test.
  if (any(isnan(g)) || any(lessThan(g, vec3(0.0))) || any(greaterThanEqual(g, vec3(dims - 1)))) return false;
  precise vec3 f = floor(g);
  ivec3 i = ivec3(f);
  precise vec3 t = g - f;
  float s000 = fieldSample(base, dims, i), s100 = fieldSample(base, dims, i + ivec3(1, 0, 0));
  float s010 = fieldSample(base, dims, i + ivec3(0, 1, 0)), s110 = fieldSample(base, dims, i + ivec3(1, 1, 0));
  float s001 = fieldSample(base, dims, i + ivec3(0, 0, 1)), s101 = fieldSample(base, dims, i + ivec3(1, 0, 1));
  float s011 = fieldSample(base, dims, i + ivec3(0, 1, 1)), s111 = fieldSample(base, dims, i + ivec3(1, 1, 1));
  precise float x00 = mix1(s000, s100, t.x), x10 = mix1(s010, s110, t.x);
  precise float x01 = mix1(s001, s101, t.x), x11 = mix1(s011, s111, t.x);
  precise float d = mix1(mix1(x00, x10, t.y), mix1(x01, x11, t.y), t.z);
  if (d >= offset) return false;
  precise vec3 grad = vec3(mix1(mix1(s100 - s000, s110 - s010, t.y), mix1(s101 - s001, s111 - s011, t.y), t.z),
                           mix1(mix1(s010 - s000, s110 - s100, t.x), mix1(s011 - s001, s111 - s101, t.x), t.z),
                           mix1(mix1(s001 - s000, s101 - s100, t.x), mix1(s011 - s010, s111 - s110, t.x), t.y));
  precise float len = length3(grad);
  if (len <= 0.0) return false;
  precise vec3 r = frictionCorrection((offset - d) * (grad / len), v, h0.b.w);
  c = r;
  return true;
}
