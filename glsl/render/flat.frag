// One colour, unlit (wireframe springs, coloured by type).
uniform vec3 u_colour;

out vec4 f_colour;

void main() {
  f_colour = vec4(u_colour, 1.0);
}
