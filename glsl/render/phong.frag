// Blinn-Phong: ambient + diffuse + specular, each term switchable to show it alone.
#include "surface_in.glsl"
#include "lighting.glsl"

uniform vec3 u_colour;
uniform vec3 u_eye;          // camera position, world space
uniform vec3 u_phong_terms;  // weights of ambient, diffuse, specular (1 shows, 0 hides)

out vec4 f_colour;

void main() {
  PhongTerms t = blinnPhong(v_position, facingNormal(normalize(v_normal)), u_eye, toLinear(u_colour));
  vec3 radiance = u_phong_terms.x * t.ambient + u_phong_terms.y * t.diffuse + u_phong_terms.z * t.specular;
  f_colour = vec4(toDisplay(radiance), 1.0);
}
