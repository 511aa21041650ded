// The one-dispatch path: every substep of a frame in one work group, the positions in shared memory
// (docs/design.md section 4, "The one-dispatch path"). For cloths that fit (GpuSolver::oneDispatchMisfit):
// on a real GPU a 50x50 frame of 30 substeps is then one dispatch of some microseconds of work instead of
// 30 x 13 dispatches, each a launch and a storage barrier. The phases of a substep are those of the
// general path's kernels, with the same pure functions in the same order, so the results are the same
// bits: forces + integrate (+ collide) as forces_integrate.comp, self-collision (+ collide) as
// self_collide.comp over a grid of its own in shared memory, the stretch passes as
// limit_stretch_coloured.comp (Gauss-Seidel, one colour after another) or limit_stretch.comp (Jacobi),
// and at the end of a frame health.comp's check. A work-group barrier takes the place of each storage
// barrier between the general path's dispatches.
//
// Each invocation owns the points lid, lid + GROUP_SIZE, ...: their displacements, pin flags and weights
// stay in registers for the whole frame, their positions in `sx`, which every invocation reads.
#define STATE_IN_PLACE
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"
#include "health.glsl"

#if SELF_COLLISION
#include "cells.glsl"
#endif
#ifndef GROUP_SIZE
#define GROUP_SIZE 128  // invocations; the solver sets it (and GROUP_POINTS) per cloth
#endif
#ifndef GROUP_POINTS
#define GROUP_POINTS 256  // the cloth's points
#endif
#define PER_INVOCATION ((GROUP_POINTS + GROUP_SIZE - 1) / GROUP_SIZE)
#ifndef GROUP_BUCKETS
#define GROUP_BUCKETS 128  // the in-group grid's buckets: a power of two, at most GROUP_SIZE
#endif

layout(local_size_x = GROUP_SIZE) in;

layout(std430, binding = kBindingPointMass) readonly buffer PointMassBuffer {
  PointMass pointMass[];
};
#ifndef GRID_SPRINGS
#define GRID_SPRINGS 0
#endif
#if GRID_SPRINGS
// A flat grid (every direction's springs one rest length): the forces and the stretch colours find each
// point's springs from the grid, so a substep reads nothing from device memory.
#include "grid_springs.glsl"
#else
layout(std430, binding = kBindingColourPartners) readonly buffer ColourPartnersBuffer {
  ColourPartner colourPartners[];  // colour c, point i: colourPartners[c * GROUP_POINTS + i]
};
#endif
#ifndef TETHER_SLOTS
#define TETHER_SLOTS 0  // tethers per point; 0: the scene has none, and the phase is not compiled
#endif
#if TETHER_SLOTS > 0
layout(std430, binding = kBindingTethers) readonly buffer TethersBuffer {
  Tether tethers[];
};
#endif

uniform uint u_substeps;  // substeps this dispatch runs
// Bit 0: forces + integrate (+ collide without self-collision); bit 1: the stretch passes; bit 2:
// self-collision + collide; bit 3: tethers. Tests run one at a time.
uniform uint u_phases;
uniform uint u_stretch_passes;  // SimParams::stretch_passes
uniform uint u_colours;         // spring colours; 0: the Jacobi stretch scheme
uniform bool u_check_health;    // end with health.comp's check of the last state (a frame), so a frame is one dispatch
#if WIND
// Time as the CPU computes it, float(double(substep) * dt), needs the double product.
uniform double u_first_substep;  // substeps taken before this dispatch
uniform double u_dt;             // s, SimParams::dt() in double
#endif

// vec3 in three floats, not vec3[] (which std430-like layouts may pad to 16 bytes): 12 bytes a point is
// what lets 50x50 fit in 32 KiB, the least a GL 4.3 device has.
shared float sx[3 * GROUP_POINTS];
shared uint sPinned[(GROUP_POINTS + 31) / 32];

vec3 loadX(uint i) {
  return vec3(sx[3u * i], sx[3u * i + 1u], sx[3u * i + 2u]);
}

void storeX(uint i, vec3 x) {
  sx[3u * i] = x.x;
  sx[3u * i + 1u] = x.y;
  sx[3u * i + 2u] = x.z;
}

#if SELF_COLLISION
// The self-collision grid of cell edge 2 * thickness, rebuilt every substep in shared memory: bucket b
// holds sGridPoints[sGridStart[b] .. sGridStart[b + 1]) in arrival order (atomics: any order; the sums
// pick their terms in ascending index, so the order never shows).
shared uint sGridStart[GROUP_BUCKETS + 1];
shared uint sGridPoints[GROUP_POINTS];
#endif

bool pinnedAt(uint j) {
  return ((sPinned[j >> 5u] >> (j & 31u)) & 1u) != 0u;
}

// barrier() alone orders shared memory for compute shaders in GLSL 4.30+; memoryBarrierShared() says so
// to any compiler that reads the older rules.
void syncGroup() {
  memoryBarrierShared();
  barrier();
}

#if WIND
vec3 pointNormal(PointMass m) {
  return gridNormal(loadX(m.normal_a), loadX(m.normal_b), loadX(m.normal_c), loadX(m.normal_d));
}
#endif

// forces_integrate.comp's body for one point, reading the neighbours from shared memory.
// `weight` is PointMass::weight, held in registers for the frame.
vec3 forcesIntegrate(uint i, inout vec3 v, float pin, vec4 weight, float time) {
  precise vec3 x = loadX(i);
  if (pin != 0.0) {
    v = vec3(0.0);
    return x;
  }
  precise vec3 f = weight.xyz;
#if GRID_SPRINGS
  // The adjacency's order: per direction, the spring ending here, then the one starting here.
  ivec2 here = gridAt(i);
  for (int d = 0; d < 6; ++d) {
    if (u_rest[d] == 0.0) continue;
    ivec2 behind = here - kDirections[d], ahead = here + kDirections[d];
    if (inGrid(behind)) f += springForce(x, loadX(gridIndex(behind)), u_rest[d], params.stiffness[d / 2]);
    if (inGrid(ahead)) f += springForce(x, loadX(gridIndex(ahead)), u_rest[d], params.stiffness[d / 2]);
  }
#else
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    f += springForce(x, loadX(neighborIndex(nb)), nb.rest, params.stiffness[neighborType(nb)]);
  }
#endif
#if WIND
  PointMass m = pointMass[i];
  precise vec3 air =
      windVelocity(x, time, params.wind_velocity.xyz, params.wind_velocity.w, params.noise_scale, params.noise_speed);
  f += windForce(pointNormal(m), v / params.dt, air, m.drag_area);
#endif
  precise vec3 vn = integrateVerlet(v, f * weight.w, params.dt2, params.keep);
  x += vn;
#if COLLIDERS && !SELF_COLLISION
  collideObjects(x, vn);
#endif
  v = vn;
  return x;
}

// limit_stretch_coloured.comp seen from one end: point i's spring of colour c moves i by exactly what the
// per-spring kernel gives that end. False where i has no spring of the colour: then it is not touched at
// all (x + 0 would turn -0 into +0).
bool stretchColoured(uint i, uint c, out vec3 corr) {
  corr = vec3(0.0);
#if GRID_SPRINGS
  ivec2 other;
  bool i_is_b;
  if (!gridPartner(gridAt(i), c, other, i_is_b)) return false;
  uint j = gridIndex(other);
  corr = stretchOneEnd(loadX(i), loadX(j), i_is_b, pinnedAt(j), u_rest[c / 2u], params.stretch_limit);
#else
  ColourPartner p = colourPartners[c * uint(GROUP_POINTS) + i];
  if (p.other == kNoPartner) return false;
  corr = stretchOneEnd(loadX(i), loadX(p.other), i > p.other, pinnedAt(p.other), p.rest, params.stretch_limit);
#endif
  return true;
}

// limit_stretch.comp's average for one point.
vec3 stretchJacobi(uint i) {
  precise vec3 x = loadX(i);
  precise vec3 sum = vec3(0.0);
  int violated = 0;
  for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
    Neighbor nb = neighbors[e];
    uint j = neighborIndex(nb);
    float share = stretchShare(false, pinnedAt(j));
    vec3 c = stretchCorrection(x, loadX(j), nb.rest, params.stretch_limit, share);
    if (c != vec3(0.0)) {
      sum += c;
      ++violated;
    }
  }
  precise vec3 c = violated > 0 ? sum / float(violated) : vec3(0.0);
  return c;
}

#if SELF_COLLISION
ivec3 orderCell(vec3 p) {
  return cellOf(p, params.inv_cell_size);
}

uint bucketOf(ivec3 cell) {
  return hashCell(cell) & uint(GROUP_BUCKETS - 1);
}

// Counting sort of the points into the buckets of their cells: counts by shared atomics, an inclusive
// scan (Hillis-Steele: log2(GROUP_BUCKETS) rounds, one bucket per invocation), then each point to its
// slot. Every invocation calls it (it has barriers).
void buildGroupGrid(uint lid) {
  uint bucket[PER_INVOCATION], slot[PER_INVOCATION];
  if (lid <= GROUP_BUCKETS) sGridStart[lid] = 0u;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    if (i >= GROUP_POINTS) continue;
    bucket[k] = bucketOf(orderCell(loadX(i)));
    slot[k] = atomicAdd(sGridStart[bucket[k]], 1u);
  }
  syncGroup();
  uint count = lid < GROUP_BUCKETS ? sGridStart[lid] : 0u;
  uint sum = count;
  for (uint offset = 1u; offset < GROUP_BUCKETS; offset <<= 1u) {
    uint before = lid < GROUP_BUCKETS && lid >= offset ? sGridStart[lid - offset] : 0u;
    syncGroup();
    sum += before;
    if (lid < GROUP_BUCKETS) sGridStart[lid] = sum;
    syncGroup();
  }
  if (lid < GROUP_BUCKETS) sGridStart[lid] = sum - count;  // exclusive
  if (lid == 0u) sGridStart[GROUP_BUCKETS] = GROUP_POINTS;
  syncGroup();
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    if (i < GROUP_POINTS) sGridPoints[sGridStart[bucket[k]] + slot[k]] = i;
  }
  syncGroup();
}

// The smallest index above `after` (any when after < 0) of a point in cell n, other than i, with a
// nonzero term; -1 if none. Buckets hold a few points, so the repeated scans cost little.
int nextInCell(uint i, vec3 x, ivec3 n, int after) {
  uint bucket = bucketOf(n);
  int best = -1;
  for (uint s = sGridStart[bucket]; s < sGridStart[bucket + 1u]; ++s) {
    uint j = sGridPoints[s];
    if (j == i || int(j) <= after || (best >= 0 && int(j) >= best)) continue;
    vec3 xj = loadX(j);
    if (orderCell(xj) != n || selfCollisionCorrection(x, xj, params.thickness) == vec3(0.0)) continue;
    best = int(j);
  }
  return best;
}

// self_collide.comp's sum for one point: the terms in the order of the 27-cell query, ascending index
// within a cell (forEachOrderedPair in src/cpu/collision_pairs.hpp).
vec3 selfCollisionOf(uint i) {
  precise vec3 x = loadX(i);
  ivec3 cell_i = orderCell(x);
  precise vec3 sum = vec3(0.0);
  int count = 0;
  for (int order = 0; order < 27; ++order) {
    ivec3 n = cell_i + ivec3(order % 3 - 1, (order / 3) % 3 - 1, order / 9 - 1);
    for (int j = nextInCell(i, x, n, -1); j >= 0; j = nextInCell(i, x, n, j)) {
      sum += selfCollisionCorrection(x, loadX(uint(j)), params.thickness);
      ++count;
    }
  }
  precise vec3 c = count > 0 ? sum / (float(count) * params.steps_per_frame) : vec3(0.0);
  return c;
}
#endif

void main() {
  const uint lid = gl_LocalInvocationID.x;
  vec3 v[PER_INVOCATION];
  float pin[PER_INVOCATION];
  vec4 weight[PER_INVOCATION];
  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    v[k] = vec3(0.0);
    pin[k] = 0.0;
    weight[k] = vec4(0.0);
    if (i >= GROUP_POINTS) continue;
    vec4 position = posIn[i];
    storeX(i, position.xyz);
    v[k] = loadDisp(i);
    pin[k] = position.w;
#if UNIFORM_MASS
    weight[k] = params.weight;
#else
    weight[k] = pointMass[i].weight;
#endif
  }
  for (uint w = lid; w < (GROUP_POINTS + 31) / 32; w += GROUP_SIZE) {
    uint bits = 0u;
    for (uint b = 0u; b < 32u && w * 32u + b < GROUP_POINTS; ++b)
      bits |= (isPinned(posIn[w * 32u + b]) ? 1u : 0u) << b;
    sPinned[w] = bits;
  }
  syncGroup();

  for (uint s = 0u; s < u_substeps; ++s) {
    if ((u_phases & 1u) != 0u) {
      float time = 0.0;
#if WIND
      time = float((u_first_substep + double(s)) * u_dt);
#endif
      // Jacobi, as the general path's ping-pong: every force reads the positions before the substep.
      vec3 x_new[PER_INVOCATION];
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint i = lid + k * GROUP_SIZE;
        if (i < GROUP_POINTS) x_new[k] = forcesIntegrate(i, v[k], pin[k], weight[k], time);
      }
      syncGroup();
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint i = lid + k * GROUP_SIZE;
        if (i < GROUP_POINTS) storeX(i, x_new[k]);
      }
      syncGroup();
    }
#if SELF_COLLISION
    if ((u_phases & 4u) != 0u) {
      buildGroupGrid(lid);
      // Jacobi, as self_collide.comp: every sum reads the positions before the pass.
      vec3 corr[PER_INVOCATION];
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint i = lid + k * GROUP_SIZE;
        corr[k] = vec3(0.0);
        if (i < GROUP_POINTS && pin[k] == 0.0) corr[k] = selfCollisionOf(i);
      }
      syncGroup();
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint i = lid + k * GROUP_SIZE;
        if (i >= GROUP_POINTS) continue;
        precise vec3 x = loadX(i) + corr[k];
        precise vec3 vc = v[k] + corr[k];  // x_prev stays where it was
#if COLLIDERS
        if (pin[k] == 0.0) collideObjects(x, vc);
#endif
        storeX(i, x);
        v[k] = vc;
      }
      syncGroup();
    }
#endif
#if TETHER_SLOTS > 0
    if ((u_phases & 8u) != 0u) {
      // tether.comp for each point: it moves only itself and reads only pins, so no barrier in between.
      for (uint k = 0u; k < PER_INVOCATION; ++k) {
        uint i = lid + k * GROUP_SIZE;
        if (i >= GROUP_POINTS || pin[k] != 0.0) continue;
        precise vec3 x = loadX(i);
        precise vec3 vc = v[k];
        for (uint t = 0u; t < uint(TETHER_SLOTS); ++t) {
          Tether tether = tethers[i * uint(TETHER_SLOTS) + t];
          if (tether.anchor == kNoTether) break;
          if (!pinnedAt(tether.anchor)) continue;
          precise vec3 c = tetherCorrection(x, loadX(tether.anchor), tether.rest, params.stretch_limit);
          x += c;
          vc += c;  // x_prev stays where it was
        }
        storeX(i, x);
        v[k] = vc;
      }
      syncGroup();
    }
#endif
    if ((u_phases & 2u) == 0u) continue;
    for (uint pass = 0u; pass < u_stretch_passes; ++pass) {
      // Gauss-Seidel: colour after colour; Jacobi (u_colours == 0): one round.
      uint rounds = max(u_colours, 1u);
      for (uint c = 0u; c < rounds; ++c) {
        vec3 corr[PER_INVOCATION];
        bool moves[PER_INVOCATION];
        for (uint k = 0u; k < PER_INVOCATION; ++k) {
          uint i = lid + k * GROUP_SIZE;
          corr[k] = vec3(0.0);
          moves[k] = i < GROUP_POINTS && pin[k] == 0.0;
          if (!moves[k]) continue;
          if (u_colours > 0u)
            moves[k] = stretchColoured(i, c, corr[k]);
          else
            corr[k] = stretchJacobi(i);
        }
        syncGroup();
        for (uint k = 0u; k < PER_INVOCATION; ++k) {
          uint i = lid + k * GROUP_SIZE;
          if (!moves[k]) continue;
          precise vec3 x = loadX(i) + corr[k];
          storeX(i, x);
          precise vec3 vc = v[k] + corr[k];  // x_prev stays where it was
          v[k] = vc;
        }
        syncGroup();
      }
    }
  }

  for (uint k = 0u; k < PER_INVOCATION; ++k) {
    uint i = lid + k * GROUP_SIZE;
    if (i >= GROUP_POINTS) continue;
    vec3 x = loadX(i);
    if (u_check_health) {
      uint flags = stateHealth(x, v[k]);
      for (uint e = offsets[i]; e < offsets[i + 1u]; ++e) {
        Neighbor nb = neighbors[e];
        if (springBlownUp(x, loadX(neighborIndex(nb)), nb.rest)) {
          flags |= kHealthOverstretched;
          break;
        }
      }
      raiseHealth(flags, i);
    }
    posIn[i] = vec4(x, pin[k]);
    storeDispInPlace(i, v[k]);
  }
}
