// Self-collision over the candidate lists (docs/design.md section 2, step 3), then the point's collisions
// where the plan fused them here (phases/contacts.glsl). Mirrors CpuSolver::selfCollide (and collide).
// Jacobi: every point reads the positions from before the pass (*In) and writes *Out, so no invocation sees
// another's result.
//
// The candidates come from the point's list (pairs.glsl); the terms are summed in the order of a 27-cell
// query of a grid of cell edge 2 * thickness, ascending index within a cell (forEachOrderedPair in
// src/cpu/collision_pairs.hpp), so the sum is the CPU's whenever the list was built.
// Needs no springs, health flags or anchors (common.glsl, pair_travel.glsl: a storage block fewer each).
#define SIM_NO_SPRINGS
#define SIM_NO_HEALTH
#define PAIR_NO_ANCHOR
#include "storage/device.glsl"
#include "storage/each_point.glsl"
#include "phases/contacts.glsl"
#include "pairs.glsl"

ivec3 orderCell(vec3 p) {
  return cellOf(p, params.inv_cell_size);
}

#ifndef TERMS_HELD
#define TERMS_HELD 8  // GpuSolverOptions::self_terms_held; 0: none held (sumListedByOrder alone)
#endif

#if TERMS_HELD > 0

// The point's own list, each candidate's position gathered once: the nonzero terms (a handful: points
// closer than 2 * thickness) are kept in cell order as they are found, stable so that one order's terms
// stay in list (ascending) order, then summed. A point with more terms than that sums them as
// sumListedByOrder does. Every loop over the held terms has a constant trip count and selects instead
// of branching on the slot, so the compiler unrolls it and the terms stay in registers: indexed by a
// variable, the arrays would go to memory, slower than the gathers they save.
bool sumListedHeld(uint i, vec3 x, inout vec3 sum, inout int count) {
  const int kEmpty = 27;  // above every cell order: an empty slot sorts last
  uint first = pairStart[i], last = pairStart[i + 1u];
  ivec3 cell_i = orderCell(x);
  vec3 term[TERMS_HELD];
  int term_order[TERMS_HELD];
  for (int t = 0; t < TERMS_HELD; ++t) {
    term[t] = vec3(0.0);
    term_order[t] = kEmpty;
  }
  int held = 0;
  for (uint s = first; s < last; ++s) {
    vec3 xj = neighbour(pairList[s]).xyz;
    vec3 c = selfCollisionCorrection(x, xj, params.thickness);
    if (c == vec3(0.0)) continue;
    int order = cellOrder(cell_i, orderCell(xj));
    if (order < 0) continue;
    if (held == TERMS_HELD) return false;
    ++held;
    // Stable: after every held term of the same or a lower order. Slots from there shift up by one.
    int at = 0;
    for (int t = 0; t < TERMS_HELD; ++t)
      at += term_order[t] <= order ? 1 : 0;
    for (int t = TERMS_HELD - 1; t > 0; --t) {
      bool shift = t > at, place = t == at;
      term[t] = shift ? term[t - 1] : place ? c : term[t];
      term_order[t] = shift ? term_order[t - 1] : place ? order : term_order[t];
    }
    if (at == 0) {
      term[0] = c;
      term_order[0] = order;
    }
  }
  precise vec3 acc = sum;
  for (int t = 0; t < TERMS_HELD; ++t)
    if (t < held) acc += term[t];
  sum = acc;
  count += held;
  return true;
}
#endif

// The same sum with no terms held: one sweep marks the cell orders present and sums the terms in list
// order, which is the sum when they all share one order (one term, or several in one cell); otherwise each
// order's terms in list order, gathering the candidates again for each order.
void sumListedByOrder(uint i, vec3 x, inout vec3 sum, inout int count) {
  precise vec3 acc = sum;
  uint first = pairStart[i], last = pairStart[i + 1u];
  ivec3 cell_i = orderCell(x);
  uint present = 0u;
  precise vec3 in_list_order = sum;
  int found = 0;
  for (uint s = first; s < last; ++s) {
    vec3 xj = neighbour(pairList[s]).xyz;
    vec3 c = selfCollisionCorrection(x, xj, params.thickness);
    if (c == vec3(0.0)) continue;
    int order = cellOrder(cell_i, orderCell(xj));
    if (order < 0) continue;
    present |= 1u << uint(order);
    in_list_order += c;
    ++found;
  }
  if (bitCount(present) <= 1) {
    sum = in_list_order;
    count += found;
    return;
  }
  while (present != 0u) {
    int order = findLSB(present);
    present &= present - 1u;
    for (uint s = first; s < last; ++s) {
      vec3 xj = neighbour(pairList[s]).xyz;
      vec3 c = selfCollisionCorrection(x, xj, params.thickness);
      if (c != vec3(0.0) && cellOrder(cell_i, orderCell(xj)) == order) {
        acc += c;
        ++count;
      }
    }
  }
  sum = acc;
}

// A point whose list did not fit the buffer is served from the 27 grid cells around its anchor, which
// hold every candidate of its list: the same terms in the same order, found by repeated scans. Slow,
// but only until the host grows the buffer (PairLists::grow, at the next health read).
//
// With `order` < 0: the mask of cell orders that have a nonzero term, and no index. Otherwise: the
// smallest candidate index >= `from` whose term is nonzero and whose cell order is `order`, or
// 0xffffffff if none.
uint scanGrid(uint i, vec3 x, ivec3 cell_i, int order, uint from, out uint present) {
  ivec3 cell = gridCell(i);
  uint best = 0xffffffffu;
  present = 0u;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 n = cell + ivec3(dx, dy, dz);
        uint bucket = hashCell(n) & params.bucket_mask;
        uint last = gridStart[bucket + 1u];
        for (uint s = gridStart[bucket]; s < last; ++s) {
          GridEntry e = gridSorted[s];
          uint j = e.index;
          if (j == i || j < from || j >= best || cellOf(entryPosition(e), params.inv_pair_cell) != n) continue;
          if (heldPair(i, j)) continue;  // as the list build leaves it out
          vec3 xj = neighbour(j).xyz;
          if (selfCollisionCorrection(x, xj, params.thickness) == vec3(0.0)) continue;
          int o = cellOrder(cell_i, orderCell(xj));
          if (order < 0) {
            if (o >= 0) present |= 1u << uint(o);
          } else if (o == order) {
            best = j;
          }
        }
      }
    }
  }
  return best;
}

void sumFromGrid(uint i, vec3 x, inout vec3 sum, inout int count) {
  precise vec3 acc = sum;
  ivec3 cell_i = orderCell(x);
  uint present, unused;
  scanGrid(i, x, cell_i, -1, 0u, present);
  while (present != 0u) {
    int order = findLSB(present);
    present &= present - 1u;
    for (uint j = scanGrid(i, x, cell_i, order, 0u, unused); j != 0xffffffffu;
         j = scanGrid(i, x, cell_i, order, j + 1u, unused)) {
      acc += selfCollisionCorrection(x, neighbour(j).xyz, params.thickness);
      ++count;
    }
  }
  sum = acc;
}

void eachPoint(uint i, vec3 x, vec3 v, float pin) {
  precise vec3 sum = vec3(0.0);
  int count = 0;
  if (pin == 0.0) {
    if (pairStart[i + 1u] <= pairState.capacity) {
#if TERMS_HELD > 0
      if (!sumListedHeld(i, x, sum, count))
#endif
        sumListedByOrder(i, x, sum, count);
    } else {
      sumFromGrid(i, x, sum, count);
    }
  }
  applyContact(contactCorrection(sum, count), count > 0, pin, x, v);
  storePoint(i, x, v, pin);
}
