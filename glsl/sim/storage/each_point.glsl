// main() of a kernel with one invocation per point over device memory (collide, forces_integrate, health,
// limit_stretch, self_collide, tether): the point's state is loaded (storage/device.glsl) and handed to the
// kernel's eachPoint, which stores what it changes. A kernel includes this after its storage and defines
// eachPoint below it.
#pragma once

layout(local_size_x = kLocalSize) in;

void eachPoint(uint i, vec3 x, vec3 v, float pin);

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  vec3 x, v;
  float pin;
  loadPoint(i, x, v, pin);
  eachPoint(i, x, v, pin);
}
