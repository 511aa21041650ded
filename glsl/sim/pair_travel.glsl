// The self-collision lists' bookkeeping and the travel check (pairs.glsl has the rest): all the
// integrate kernel needs of the lists, declared apart so that it holds two storage blocks, not six.
#pragma once

#include "physics.glsl"

layout(std430, binding = kBindingPairControl) buffer PairControlBuffer {
  PairState pairState;
  PairDispatch pairDispatch;
};
// self_collide.comp, which reads no anchor, defines PAIR_NO_ANCHOR: one storage block fewer.
#ifndef PAIR_NO_ANCHOR
layout(std430, binding = kBindingPairAnchor) buffer PairAnchorBuffer {
  vec4 pairAnchor[];
};

// `!(d2 <= travel2)` so that a non-finite position, or a list never built (travel2 < 0), counts as
// moved. Every writer stores the same 1, so plain stores suffice.
void checkPairTravel(uint i, vec3 x) {
  precise vec3 d = x - pairAnchor[i].xyz;
  if (!(dot3(d, d) <= pairState.travel2)) pairState.stale = 1u;
}
#endif
