// Multiplies every value by FACTOR (a define), through a helper in an included file.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Values {
  float values[];
};

uniform uint count;

#include "scale.glsl"
#include "scale.glsl"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i < count) values[i] = scale(values[i]);
}
