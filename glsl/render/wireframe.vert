// Springs as lines, pulled from the same position buffer as the surface (one element buffer of
// line pairs per spring type).
#include "render_bindings.h"

layout(std430, binding = RENDER_BINDING_POSITIONS) readonly buffer Positions {
  vec4 positions[];
};

// The solver's blow-up flags, read on the GPU: a cloth whose flags are raised is not drawn, so no frame of
// garbage reaches the screen while the host learns of it a frame late (Solver::recentHealth). Colliders
// and the CPU solvers' uploads bind a buffer of zeros.
layout(std430, binding = RENDER_BINDING_HEALTH) readonly buffer ClothHealth {
  uint health_flags;
};

uniform mat4 u_view_projection;

void main() {
  gl_Position = u_view_projection * vec4(positions[gl_VertexID].xyz, 1.0);
  if (health_flags != 0u) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // beyond a clip plane: not drawn
}
