// What a mesh cloth's points do not share (PointMass, glsl/shared/layout.h): their weight and inverse mass,
// their wind drag and normal stencil. A grid's points all weigh SimParams::weight (UNIFORM_MASS), so its
// kernels read this buffer only for wind. A storage block of its own: a kernel that reads none of it does
// not include this file (Mesa counts every declared block, common.glsl).
#pragma once

#include "common.glsl"

layout(std430, binding = kBindingPointMass) readonly buffer PointMassBuffer {
  PointMass pointMass[];
};

// gravity * mass (xyz) and 1 / mass (w) of point i.
vec4 pointWeight(uint i) {
#if UNIFORM_MASS
  return params.weight;
#else
  return pointMass[i].weight;
#endif
}
