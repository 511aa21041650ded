// Each point to its bucket's range, at the slot its atomic arrival gave it (see grid.glsl).
#include "lists_each_point.glsl"
#include "grid.glsl"

void eachIndex(uint i) {
  scatterPoint(i);
}
