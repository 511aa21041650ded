// Positions in shared memory, 12 bytes a point (vec3[] may be padded to 16: 12 is what lets 50x50 fit in
// 32 KiB, the least a GL 4.3 device has), and a pin bit a point unless the including storage defines
// SHARED_NO_PINS: the one-dispatch kernel's whole cloth (group.glsl) and the tiled kernels' block and ring
// (tile.glsl, forces_integrate_tiled.comp). The storage defines SHARED_POINTS, the points it holds, first.
#pragma once

shared float sx[3 * SHARED_POINTS];
#ifndef SHARED_NO_PINS
shared uint sPinned[(SHARED_POINTS + 31) / 32];
#endif

vec3 loadX(uint s) {
  return vec3(sx[3u * s], sx[3u * s + 1u], sx[3u * s + 2u]);
}

void storeX(uint s, vec3 x) {
  sx[3u * s] = x.x;
  sx[3u * s + 1u] = x.y;
  sx[3u * s + 2u] = x.z;
}

#ifndef SHARED_NO_PINS
bool pinnedAt(uint s) {
  return ((sPinned[s >> 5u] >> (s & 31u)) & 1u) != 0u;
}
#endif

// barrier() alone orders shared memory for compute shaders in GLSL 4.30+; memoryBarrierShared() says so
// to any compiler that reads the older rules.
void syncGroup() {
  memoryBarrierShared();
  barrier();
}

#ifdef PER_INVOCATION
// The registers of slot lid + k * GROUP_SIZE that the stretch limit moves with its position: the
// displacement (x_prev stays where it was) and the position's w, the pin flag.
vec3 slotV[PER_INVOCATION];
float slotPin[PER_INVOCATION];

void moveSlot(uint s, uint k, vec3 c) {
  precise vec3 x = loadX(s) + c;
  storeX(s, x);
  precise vec3 v = slotV[k] + c;
  slotV[k] = v;
}
#endif
