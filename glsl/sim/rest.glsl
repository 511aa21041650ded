// Which self-collision pairs the springs hold (physics::heldAtRest): closer than the contact distance in the
// cloth's rest shape. Declares its storage block only where the plan says some pair may be held
// (HELD_AT_REST); elsewhere no pair is.
#pragma once

#include "common.glsl"
#include "physics.glsl"
#ifndef HELD_AT_REST
#define HELD_AT_REST 0
#endif

#if HELD_AT_REST
layout(std430, binding = kBindingRest) readonly buffer RestBuffer {
  float restPosition[];  // 3 a point, packed: the topology's initial positions rounded to float
};

vec3 restOf(uint i) {
  return vec3(restPosition[3u * i], restPosition[3u * i + 1u], restPosition[3u * i + 2u]);
}

bool heldPair(uint i, uint j) {
  precise float range = 2.0 * params.thickness;
  return heldAtRest(restOf(i), restOf(j), range);
}
#else
bool heldPair(uint i, uint j) {
  return false;
}
#endif
