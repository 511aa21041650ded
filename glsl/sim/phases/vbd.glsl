// Vertex Block Descent (Chen et al. 2024; docs/design.md section 2, "Vertex Block Descent") of one point,
// mirroring CpuSolver::solveVbd: its springs' forces and Hessians gathered into its 3x3 block with the
// inertia m/dt^2 I, and the Newton step that block gives, which moves x and v alike. Reads the neighbours
// through the storage's neighbour(j).
#pragma once

#include "../common.glsl"
#include "../physics.glsl"

// Point i at x with inverse mass w. `pull`: the inertia's gradient -m/dt^2 (x - y) towards the prediction y,
// 0 in a substep's first sweep (x is still y there).
vec3 vbdStepOf(uint i, vec3 x, float inertia, vec3 pull) {
  vec3 f = pull;
  vec3 h_diag = vec3(inertia);
  vec3 h_off = vec3(0.0);
  // Ascending spring index, the CPU's order, so the sums round alike; disabled types are not in the GPU's
  // adjacency.
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    vbdAddSpring(x, neighbour(neighborIndex(nb)).xyz, nb.rest, params.stiffness[neighborType(nb)], f, h_diag, h_off);
  }
  precise vec3 dx = vbdStep(f, h_diag, h_off);
  return dx;
}
