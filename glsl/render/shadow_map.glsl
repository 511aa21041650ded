// Shadow-map lookup (Williams 1978) with 3x3 percentage-closer filtering (Reeves et al. 1987). The light's
// frustum holds every caster (the cloth wherever it went, the colliders): a point outside it is lit, and a
// receiver beyond the far plane (the far end of a floor) is compared as lying just inside it, so a caster's
// shadow reaches it whole.
#pragma once

#include "lighting.glsl"

in vec4 v_light_clip;

uniform sampler2DShadow u_shadow_map;

// 1 where the light sees this point, 0 in shadow, in between at a shadow's edge.
float lightVisibility(vec3 position, vec3 n) {
  vec3 p = v_light_clip.xyz / v_light_clip.w * 0.5 + 0.5;
  if (v_light_clip.w <= 0.0 || any(lessThan(p.xy, vec2(0.0))) || any(greaterThan(p.xy, vec2(1.0)))) return 1.0;
  // Slope-scaled bias: grazing surfaces need more to avoid shadow acne.
  float bias = 0.0015 + 0.004 * (1.0 - abs(dot(n, lightDirection(position))));
  float depth = clamp(p.z, 0.0, 0.9999) - bias;
  vec2 texel = 1.0 / vec2(textureSize(u_shadow_map, 0));
  float lit = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      lit += texture(u_shadow_map, vec3(p.xy + vec2(dx, dy) * texel, depth));
  return lit / 9.0;
}
