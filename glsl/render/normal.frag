// Normal shading: the world-space normal facing the viewer, mapped from [-1, 1] to a colour.
#include "surface_in.glsl"

out vec4 f_colour;

void main() {
  f_colour = vec4(0.5 * facingNormal(normalize(v_normal)) + 0.5, 1.0);
}
