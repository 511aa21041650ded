// The hash-grid count on its own, for a state uploaded from the host (tests, a drag between substeps
// is not one: integrate recounts). In a normal substep the count is fused into forces_integrate.comp.
#include "grid.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  countIntoGrid(i, posIn[i].xyz);
}
