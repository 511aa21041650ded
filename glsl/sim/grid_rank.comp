// Stable order within each bucket: a point's slot is the number of smaller indices in its bucket.
#include "grid.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i < params.point_count) rankPoint(i);
}
