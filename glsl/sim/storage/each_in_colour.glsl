// main() of a Gauss-Seidel colour's kernel (limit_stretch_coloured, xpbd_coloured, vbd_coloured): one
// invocation per element of the colour's range [u_first, u_first + u_count) of the plan's dispatch (springs
// or points, in colour order), handed to the kernel's eachInColour. A kernel includes this after its storage
// (device.glsl, with STATE_IN_PLACE) and defines eachInColour below it.
#pragma once

layout(local_size_x = kLocalSize) in;

uniform uint u_first;  // the colour's first element
uniform uint u_count;  // elements in the colour

void eachInColour(uint index);

void main() {
  uint k = globalIndex();
  if (k < u_count) eachInColour(u_first + k);
}
