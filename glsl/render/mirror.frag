// Mirror: the environment cube map in the direction of the view ray reflected about the normal.
#include "colour.glsl"
#include "surface_in.glsl"

uniform samplerCube u_environment;
uniform vec3 u_eye;

out vec4 f_colour;

void main() {
  vec3 n = facingNormal(normalize(v_normal));
  vec3 view = normalize(v_position - u_eye);
  vec3 r = reflect(view, n);
  // Schlick's Fresnel term with a metal's 70% reflectance head-on, so the mirror stays visible against
  // the very sky it reflects.
  float fresnel = 0.7 + 0.3 * pow(1.0 - max(dot(-view, n), 0.0), 5.0);
  f_colour = vec4(toDisplay(fresnel * texture(u_environment, r).rgb), 1.0);  // an sRGB texture samples linear
}
