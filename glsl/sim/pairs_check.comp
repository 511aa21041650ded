// The travel check on its own, for a state uploaded from the host (tests); in a normal substep it is
// fused into forces_integrate.comp.
#include "lists_each_point.glsl"
#include "pair_travel.glsl"

void eachIndex(uint i) {
  checkPairTravel(i, posIn[i].xyz);
}
