// The environment cube map behind the scene, so the mirror's reflections have their source in view.
#include "colour.glsl"

in vec2 v_ndc;

uniform samplerCube u_environment;
uniform mat4 u_inverse_view_projection;

out vec4 f_colour;

void main() {
  vec4 near_point = u_inverse_view_projection * vec4(v_ndc, -1.0, 1.0);
  vec4 far_point = u_inverse_view_projection * vec4(v_ndc, 1.0, 1.0);
  vec3 direction = far_point.xyz / far_point.w - near_point.xyz / near_point.w;
  f_colour = vec4(toDisplay(texture(u_environment, direction).rgb), 1.0);
}
