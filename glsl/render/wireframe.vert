// Springs as lines, pulled from the same position buffer as the surface (one element buffer of
// line pairs per spring type).
#include "render_bindings.h"

layout(std430, binding = RENDER_BINDING_POSITIONS) readonly buffer Positions {
  vec4 positions[];
};

uniform mat4 u_view_projection;

void main() {
  gl_Position = u_view_projection * vec4(positions[gl_VertexID].xyz, 1.0);
}
