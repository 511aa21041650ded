// Each point to its bucket's range, at the slot its atomic arrival gave it (see grid.glsl).
#include "grid.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) scatterPoint(i);
}
