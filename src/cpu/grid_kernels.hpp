// The float solver's passes on a grid cloth, several points at once (SIMD across points): on a grid every
// spring is a fixed offset, so a row of points finds its neighbours, and the springs of a stretch-limit
// colour their ends, at consecutive addresses. Each point's (each spring's) operations are those of the
// general path (cpu/physics.hpp) in the same order, one lane each, so the bytes are the general path's
// (tests/grid_path_test.cpp holds the two together). The positions are worked on as a structure of arrays
// in a padded layout (GridShape), copied from and back to the solver's vec3 arrays around a pass.
#pragma once

#include <cstddef>
#include <cstdint>

namespace drape {

// Point (x, y) of a W x H grid at (y + kTop) * stride + kLeft + x. The padding is zero and never written: the
// neighbour reads of a row's first and last points, and the lanes past a row's end, land in it, so no read
// or write of a row ever reaches another row's points (threads work on whole rows).
struct GridShape {
  static constexpr int kLeft = 4, kTop = 2;
  int W = 0, H = 0, stride = 0;
  std::size_t size = 0;  // floats per array

  static GridShape of(int w, int h);
  std::ptrdiff_t at(int x, int y) const;  // not inline: no AVX2 copy of it may exist (cpu/simd.hpp)
};

// The six grid directions (core/colouring.hpp, kGridDirections) and, per direction, the spring's stiffness
// (enabled = false for a disabled type) and rest lengths, each at its start point a in the padded layout.
struct GridSprings {
  const float* rest[6] = {};
  float k[6] = {};
  bool enabled[6] = {};
};

struct GridForceArgs {
  GridShape shape;
  const float *x, *y, *z;  // positions, padded layout
  const float* mass;       // per point, padded layout
  float gravity[3] = {};
  GridSprings springs;
  float* forces;  // vec3 per point, in point order (CpuSolver's forces_)
};

struct GridStretchArgs {
  GridShape shape;
  float *x, *y, *z;     // positions, padded layout, updated in place
  float *vx, *vy, *vz;  // displacements, the same corrections added (nullptr: not kept)
  const float* pinned;  // all bits set where pinned, padded layout
  GridSprings springs;
  float limit = 1.1f;
};

// One instruction set's kernels. Each works on the rows [y0, y1) of the grid (for a stretch colour, the
// rows where its springs start), so a team of threads can split a pass by rows.
struct GridKernels {
  const char* name;  // "sse2", "avx2"
  int width;         // lanes
  // vec3 array <-> three padded arrays
  void (*toSoa)(const GridShape&, const float* aos, float* x, float* y, float* z, int y0, int y1);
  void (*fromSoa)(const GridShape&, const float* x, const float* y, const float* z, float* aos, int y0, int y1);
  // Gravity and every enabled spring, summed per point in the adjacency's order (docs/design.md).
  void (*forces)(const GridForceArgs&, int y0, int y1);
  // Provot's stretch limit over the springs of colour 2 * direction + parity (core/colouring.hpp).
  void (*stretchColour)(const GridStretchArgs&, int direction, int parity, int y0, int y1);
  // Verlet in displacement form (physics::integrateVerlet, then x += v) over vec3 arrays seen as floats,
  // [first, last) in floats: per float its point's inverse mass and pin mask (all bits set: pinned, which
  // keeps x and sets v to +0). Not grid-specific: it needs no neighbours.
  void (*integrate)(float* x, float* v, const float* f, const float* inv_mass3, const float* pinned3, float dt2,
                    float keep, long long first, long long last);
  // Whether any candidate j in [begin, end) of point i is within self-collision range of it, by the test of
  // physics::selfCollisionCorrection (NaN counts as in range, as there): false means the point's sum is
  // empty. x is the vec3 array seen as floats. Not grid-specific.
  bool (*anyInRange)(const float* x, const std::uint32_t* begin, const std::uint32_t* end, std::size_t i,
                     float thickness);
  // Probes of this machine's peak with these instructions (cpu/machine_peak.hpp); each returns a value that
  // depends on all its work, so that none of it can be left out. Independent chains, so throughput counts:
  // 6 multiplies and 6 adds per lane and rep (no fused multiply-add: the build forbids it)
  float (*probeAddMul)(long long reps);
  // 4 square roots and 4 divisions per lane and rep, the two operations every spring needs
  float (*probeDivSqrt)(long long reps);
  // STREAM's triad a = b + s c over n floats (n a multiple of the width): 12 bytes per element
  void (*probeTriad)(float* a, const float* b, const float* c, long long n, float s);
};

enum class GridIsa { Auto, Sse2, Avx2 };

// The kernels for `isa`; Auto picks AVX2 where the CPU has it (checked at run time: the binary runs on any
// x86-64), else SSE2. Throws std::runtime_error for Avx2 on a CPU without it.
const GridKernels& gridKernels(GridIsa isa = GridIsa::Auto);
bool cpuHasAvx2();

const GridKernels& gridKernelsSse2();
const GridKernels& gridKernelsAvx2();

}  // namespace drape
