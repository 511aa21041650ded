// The ground, in every shading model: a matte surface that receives the shadows of the cloth and the
// colliders (shadow_map.glsl), fading into the background away from the scene so that the floor has no
// hard far edge. A shadow keeps part of the direct light, standing in for the light the room would bounce
// into it: the ground under a cloth reads as shade, not as a hole.
#include "surface_in.glsl"
#include "lighting.glsl"
#include "shadow_map.glsl"

uniform vec3 u_colour;
uniform vec3 u_background;  // display encoding, as the clear colour
uniform vec4 u_fade;        // xyz: the scene's centre on the ground; w: distance at which the ground is gone
uniform bool u_shadows;

out vec4 f_colour;

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  vec3 colour = toLinear(u_colour);
  const float kShade = 0.35;  // of the direct light a shadow keeps
  float visibility = u_shadows ? lightVisibility(v_position, n) : 1.0;
  float lit = max(dot(n, lightDirection(v_position)), 0.0) * mix(kShade, 1.0, visibility);
  vec3 radiance = kAmbient * colour + colour * irradiance(v_position) * lit;
  float fade = smoothstep(0.35 * u_fade.w, u_fade.w, distance(v_position, u_fade.xyz));
  f_colour = vec4(mix(toDisplay(radiance), u_background, fade), 1.0);
}
