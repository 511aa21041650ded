// Shadow-mapped Blinn-Phong: the diffuse and specular terms are kept only where the light sees this point
// (shadow_map.glsl).
#include "surface_in.glsl"
#include "lighting.glsl"
#include "shadow_map.glsl"

uniform vec3 u_colour;
uniform vec3 u_eye;

out vec4 f_colour;

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  PhongTerms t = blinnPhong(v_position, n, u_eye, toLinear(u_colour));
  f_colour = vec4(toDisplay(t.ambient + lightVisibility(v_position, n) * (t.diffuse + t.specular)), 1.0);
}
