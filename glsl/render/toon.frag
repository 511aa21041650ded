// Toon (cel) shading: the diffuse term quantised into u_toon_levels flat bands, a hard-edged
// highlight and a dark outline where the surface turns away from the viewer.
#include "surface_in.glsl"
#include "lighting.glsl"

uniform vec3 u_colour;
uniform vec3 u_eye;
uniform int u_toon_levels;  // >= 2

out vec4 f_colour;

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  vec3 l = lightDirection(v_position);
  vec3 v = normalize(u_eye - v_position);
  float levels = float(max(u_toon_levels, 2));
  float band = ceil(max(dot(n, l), 0.0) * levels) / levels;
  vec3 colour = toLinear(u_colour) * (0.3 + 0.7 * band);
  if (dot(n, l) > 0.0 && pow(max(dot(n, normalize(l + v)), 0.0), 4.0 * kShininess) > 0.5) colour = vec3(1.0);
  if (dot(n, v) < 0.2) colour = 0.02 * toLinear(u_colour);
  f_colour = vec4(toDisplay(colour), 1.0);
}
