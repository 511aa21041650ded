// Texture mapping: the fabric texture at the vertex UVs. CS184 shows the texture unlit; it is lit
// here (ambient + diffuse) so that the folds of the cloth stay visible.
#include "surface_in.glsl"
#include "lighting.glsl"

uniform sampler2D u_texture;

out vec4 f_colour;

void main() {
  vec3 albedo = texture(u_texture, v_uv).rgb;  // an sRGB texture: linear after sampling
  vec3 n = facingNormal(normalize(v_normal));
  vec3 light = kAmbient + irradiance(v_position) * max(dot(n, lightDirection(v_position)), 0.0);
  f_colour = vec4(toDisplay(albedo * light), 1.0);
}
