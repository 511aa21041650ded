// Picking: the cloth point nearest to each pixel (its grid coordinates are the UVs times the grid
// size minus one), and the world position under the pixel, read back for the one pixel clicked.
#include "surface_in.glsl"

uniform vec2 u_grid_size;  // (W, H)

layout(location = 0) out uint f_point;
layout(location = 1) out vec4 f_position;

void main() {
  vec2 grid = round(v_uv * (u_grid_size - 1.0));
  // +1 so that 0 means "no cloth" after a clear to zero.
  f_point = uint(grid.y * u_grid_size.x + grid.x) + 1u;
  f_position = vec4(v_position, 1.0);
}
