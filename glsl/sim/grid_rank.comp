// Stable order within each bucket: a point's slot is the number of smaller indices in its bucket.
#include "lists_each_point.glsl"
#include "grid.glsl"
#include "pair_travel.glsl"

void eachIndex(uint i) {
  rankPoint(i, pairAnchor[i].xyz);
}
