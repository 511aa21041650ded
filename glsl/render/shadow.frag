// Shadow-mapped Blinn-Phong (Williams 1978): the diffuse and specular terms are kept only where the
// light sees this point, tested against the depth map rendered from the light with 3x3 percentage-
// closer filtering (Reeves et al. 1987) to soften the staircase.
#include "surface_in.glsl"
#include "lighting.glsl"

in vec4 v_light_clip;

uniform vec3 u_colour;
uniform vec3 u_eye;
uniform sampler2DShadow u_shadow_map;

out vec4 f_colour;

float lightVisibility(vec3 n) {
  vec3 p = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
  if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
  // Slope-scaled bias: grazing surfaces need more to avoid shadow acne.
  float bias = 0.0015 + 0.004 * (1.0 - abs(dot(n, lightDirection(v_position))));
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_map, 0));
  float lit = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      lit += texture(u_shadow_map, vec3(p.xy + vec2(dx, dy) * texel, p.z - bias));
  return lit / 9.0;
}

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  PhongTerms t = blinnPhong(v_position, n, u_eye, toLinear(u_colour));
  f_colour = vec4(toDisplay(t.ambient + lightVisibility(n) * (t.diffuse + t.specular)), 1.0);
}
