// The state in device memory, as the general path's per-point kernels see it: a point's own state by its
// index, its neighbours' positions by gathers from the current copy (*In). Each kernel includes one storage
// (this file, group.glsl or tile.glsl), which defines what the phases (glsl/sim/phases) read points through:
//   vec4 neighbour(uint j)   point j's position, w its pin flag
#pragma once

#include "../common.glsl"

vec4 neighbour(uint j) {
  return posIn[j];
}

void loadPoint(uint i, out vec3 x, out vec3 v, out float pin) {
  vec4 position = posIn[i];
  x = position.xyz;
  v = loadDisp(i);
  pin = position.w;
}

// Ping-pong: into the other copy (*Out), which the next pass reads.
void storePoint(uint i, vec3 x, vec3 v, float pin) {
  posOut[i] = vec4(x, pin);
  storeDisp(i, v);
}

#ifdef STATE_IN_PLACE
// In place: for passes where a point writes only itself and reads nothing another invocation writes.
void storePointInPlace(uint i, vec3 x, vec3 v, float pin) {
  posIn[i] = vec4(x, pin);
  storeDispInPlace(i, v);
}

// Point i, at `position` (w its pin flag), moved in place by a correction c of a Gauss-Seidel colour: x and v
// alike, so x_prev stays where it was.
void movePointInPlace(uint i, vec4 position, vec3 c) {
  precise vec3 x = position.xyz + c;
  precise vec3 v = loadDisp(i) + c;
  storePointInPlace(i, x, v, position.w);
}
#endif
