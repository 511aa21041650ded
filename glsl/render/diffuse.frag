// Lambertian shading: kd * I / r^2 * max(0, n . l).
#include "surface_in.glsl"
#include "lighting.glsl"

uniform vec3 u_colour;  // kd

out vec4 f_colour;

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  vec3 radiance = toLinear(u_colour) * irradiance(v_position) * max(dot(n, lightDirection(v_position)), 0.0);
  f_colour = vec4(toDisplay(radiance), 1.0);
}
