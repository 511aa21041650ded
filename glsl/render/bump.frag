// Bump mapping (and, with DISPLACE in surface.vert, displacement mapping): Blinn-Phong with the
// normal perturbed by the height map in the tangent frame.
#include "surface_in.glsl"
#include "lighting.glsl"
#include "tangent_space.glsl"

uniform vec3 u_colour;
uniform vec3 u_eye;

out vec4 f_colour;

void main() {
  // Perturb in the frame of the front side, then turn to the side being seen.
  vec3 n = facingNormal(bumpedNormal(v_normal, v_uv));
  PhongTerms t = blinnPhong(v_position, n, u_eye, toLinear(u_colour));
  f_colour = vec4(toDisplay(t.ambient + t.diffuse + t.specular), 1.0);
}
