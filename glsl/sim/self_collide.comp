// Self-collision (docs/design.md section 2, step 3), then the point's sphere and plane collisions, which only
// need its own corrected state. Mirrors CpuSolver::selfCollide (and collide). Jacobi: every point reads
// the positions from before the pass (*In) and writes *Out, so no invocation sees another's result.
#include "common.glsl"
#include "physics.glsl"
#include "collide.glsl"
#include "grid.glsl"

layout(local_size_x = kLocalSize) in;

void main() {
  uint i = globalIndex();
  if (i >= params.point_count) return;
  precise vec3 x = posIn[i].xyz;
  precise vec3 v = dispIn[i].xyz;
  float pin = dispIn[i].w;
  precise vec3 sum = vec3(0.0);
  int count = 0;
  if (pin == 0.0) {
    ivec3 cell = gridCell(i);
    // HashGrid::forEachCandidate's order: 27 cells in z, y, x order, ascending index within a cell.
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          ivec3 n = cell + ivec3(dx, dy, dz);
          uint bucket = hashCell(n) & params.bucket_mask;
          uint last = gridStart[bucket + 1u];
          for (uint s = gridStart[bucket]; s < last; ++s) {
            uint j = gridSorted[s];
            if (j == i || gridCell(j) != n) continue;  // a bucket can hold other cells' points
            vec3 c = selfCollisionCorrection(x, posIn[j].xyz, params.thickness);
            if (c != vec3(0.0)) {
              sum += c;
              ++count;
            }
          }
        }
      }
    }
  }
  precise vec3 correction = count > 0 ? sum / (float(count) * params.steps_per_frame) : vec3(0.0);
  x += correction;
  v += correction;  // x_prev stays where it was
#if COLLIDERS
  if (pin == 0.0) collideObjects(x, v);
#endif
  posOut[i] = vec4(x, 1.0);
  dispOut[i] = vec4(v, pin);
}
