// The float solver's passes on a grid cloth, several points at once (SIMD across points): on a grid every
// spring is a fixed offset, so a row of points finds its neighbours, and the springs of a stretch-limit
// colour their ends, at consecutive addresses. Each point's (each spring's) operations are those of the
// general path (cpu/physics.hpp) in the same order, one lane each, so the bytes are the general path's
// (tests/grid_path_test.cpp holds the two together). The positions are worked on as a structure of arrays
// in a padded layout (GridShape), copied from and back to the solver's vec3 arrays around a pass, or kept there
// from pass to pass (CpuSolver::gridIntegrates).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace drape {

// Point (x, y) of a W x H grid at (y + kTop) * stride + kLeft + x. The padding is zero and never written: the
// neighbour reads of a row's first and last points, and the lanes past a row's end, land in it, so no read
// or write of a row ever reaches another row's points (threads work on whole rows). kLeft and the stride are
// multiples of sixteen floats, so that in arrays that start on a cache line (cpu/aligned.hpp) every row's first
// point starts one: the kernels' loads and stores of a point's own vector then each touch one line, not two (the
// neighbours' loads, a column or two aside, still cross). Two columns would do for the neighbours; the 14 more made
// CS184's 50 x 50 files 2-7% faster (docs/results/cpu_speed.md).
struct GridShape {
  static constexpr int kLeft = 16, kTop = 2;
  static constexpr int kMaxWidth = 16;  // the widest instruction set's lanes (AVX-512)
  int W = 0, H = 0, stride = 0;
  std::size_t size = 0;  // floats per array

  static GridShape of(int w, int h);
  std::ptrdiff_t at(int x, int y) const;  // not inline: no AVX2 copy of it may exist (cpu/simd.hpp)
};

// The six grid directions (core/topology.hpp, kGridDirections) and, per direction, the spring's stiffness
// (enabled = false for a disabled type) and rest lengths, each at its start point a in the padded layout.
struct GridSprings {
  const float* rest[6] = {};
  float k[6] = {};
  bool enabled[6] = {};
};

struct GridIntegrateArgs;

// The health check's quick look (core/health.hpp, quickHealthy) on the padded arrays of x and v: per direction the
// limit of each spring at its start (quickLimit2, +inf where none starts), or nullptr where the direction's type is
// off.
struct GridHealthArgs {
  GridShape shape;
  const float *x, *y, *z, *vx, *vy, *vz;
  const float* limit2[6] = {};
  float bound = 0;  // QuickHealth::bound
};

struct GridForceArgs {
  GridShape shape;
  const float *x, *y, *z;  // positions, padded layout
  const float* mass;       // per point, padded layout
  float gravity[3] = {};
  GridSprings springs;
  float* forces;  // vec3 per point, in point order (CpuSolver's forces_)
  // Where given, integrateRows of rows [integrate_from, integrate_to) in the same sweep, each row two rows after
  // its forces, once no later row's forces read its positions (a spring spans up to two rows)
  const GridIntegrateArgs* integrate = nullptr;
  int integrate_from = 0, integrate_to = 0;
};

struct GridStretchArgs {
  GridShape shape;
  float *x, *y, *z;     // positions, padded layout, updated in place
  float *vx, *vy, *vz;  // displacements, the same corrections added (nullptr: not kept)
  const float* pinned;  // all bits set where pinned, padded layout
  GridSprings springs;  // XPBD: k[d] holds the direction's compliance over dt^2, alpha_tilde
  float limit = 1.1f;
  const float* inv_mass = nullptr;  // XPBD: inverse masses, padded layout
  float* lambda[6] = {};            // XPBD of several sweeps: each spring's multiplier at its start; else none (0)
  // Per row, 1 where a coordinate of a position or displacement may be -0 (or nullptr: anywhere). The stretch
  // limit skips what cannot change elsewhere: a colour's sweep makes no new -0 (x + c is -0 only for two -0s).
  const std::uint8_t* signed_rows = nullptr;
};

// Verlet in displacement form on the padded arrays' rows, as GridKernels::integrate computes each coordinate, the
// forces read from the solver's vec3 array. The new positions and displacements go to the padded arrays, where the
// substep's passes after read them, and the positions also to the solver's vec3 array where self-collision reads them
// there (CpuSolver::integrate); the displacements stay in the arrays until the solver's next copy back.
struct GridIntegrateArgs {
  GridShape shape;
  float *x, *y, *z, *vx, *vy, *vz;  // padded layout, updated in place
  const float* pinned;              // all bits set where pinned, padded layout
  const float* inv_mass;            // padded layout
  const float* forces;              // vec3 per point, in point order
  float* aos_x;                     // the positions as a vec3 array, written; nullptr: not written
  float dt2 = 0, keep = 0;
  std::uint8_t* signed_rows;  // per row: 1 where a new coordinate is -0, else 0 (GridStretchArgs::signed_rows)
};

// VBD's sweeps over one colour's points: each point's Newton step (sweep 0 from the prediction).
struct GridVbdArgs {
  GridShape shape;
  float *x, *y, *z;       // positions, padded layout, updated in place
  float *vx, *vy, *vz;    // displacements, the same steps added (nullptr: not kept)
  const float* pinned;    // all bits set where pinned, padded layout
  const float* inv_mass;  // padded layout
  GridSprings springs;    // rest lengths and stiffness per direction
  float dt2 = 0;          // dt^2 as the solver rounds it
  // The colours' points (PointColouring's order): each one's padded index, column and row (exact floats)
  const std::int32_t* padded;
  const float *column, *row;
  // Several sweeps: each point's prediction, padded layout, written in sweep 0 and read by the later ones
  // (nullptr: a single sweep).
  float *target_x = nullptr, *target_y = nullptr, *target_z = nullptr;
  int sweep = 0;
};

// A self-collision list build's candidates of one point, in the order of the build's spatial grid: their
// positions, and on a grid cloth their column and row (exact small integers as floats) with which the build
// passes over the pairs the springs hold or the stencil tests.
inline constexpr std::size_t kPairScanPad = 16;  // at least every instruction set's width
struct PairScanArgs {
  // Slot by slot, each readable kPairScanPad slots past the last slot scanned (the lanes there are dropped):
  const float *x, *y, *z;  // candidate positions
  const float *u, *v;      // candidate grid columns and rows (unused where a2 = b2 = 0)
  float px, py, pz;        // the point's position
  float pu, pv;            // its column and row
  float reach2;            // (range + margin)^2
  float a2, b2;            // the grid's squared steps along u and v at rest
  // An offset whose nominal squared distance du^2 a2 + dv^2 b2 is under near_below is held or on the stencil.
  float near_below;
  // scanCell: a candidate at a squared distance of near2 or more (not a NaN) is a far one, its slot marked kFarSlot
  float near2;
};
// The mark of a far candidate's slot from scanCell (a slot is below 2^31: CollisionPairs takes at most 2^31 points)
inline constexpr std::uint32_t kFarSlot = std::uint32_t(1) << 31;

// A range of candidate slots for GridKernels::scanCell: own where it is the cell's own row, whose slots up to each
// point's own are not its candidates.
struct CellRange {
  std::uint32_t first, last;
  bool own;
};
inline constexpr int kCellRanges = 5;  // a cell's forward ranges at most (HashGrid::forEachForwardRange)

// A self-collision pair as a build files it (CollisionPairs::Pair): its lower end, and its upper end with kFarSlot set
// where it is a far entry.
struct FiledPair {
  std::uint32_t lower, upper;
};
// GridKernels::filePairs' tables, of a grid cloth's build
struct PairFileArgs {
  const std::uint32_t* sorted;  // the point at each slot of the build's grid order
  const std::uint32_t* uv;      // each point's column | row << 16
  const std::int32_t* kind;  // CollisionPairs::OffsetKind of each offset (du, dv) of the box [-box, box]^2, row by row
  int box;
  std::uint32_t split;  // a pair whose lower end is under split goes to the first output, the others to the second
};

// A self-collision pair within range, as GridKernels::pairTerms finds it: physics::selfCollisionCorrections
// from both ends and the cellOrder of each end's partner (CollisionPairs' sum order).
struct PairTermOut {
  std::uint32_t k;                // the pair's entry
  std::int32_t order_i, order_j;  // -1: the two cells are not neighbours; order_i -2: a NaN distance (not computed)
  float ci[3], cj[3];
};

// Self-collision's stencil of a grid cloth (cpu/collision_pairs.hpp): the pairs of a point and its partner at grid
// offset (du[k], dv[k]), k < count, that lies on the grid, is not held at rest where mixed[k] (physics::heldAtRest
// on the rest positions), and is within sqrt(range2) now (the test of physics::selfCollisionCorrection; a NaN
// distance counts). The offsets are the stencil's forward half (one of each +-pair), so each pair comes once, from
// its lower point.
struct GridStencilArgs {
  GridShape shape;
  const float *x, *y, *z;     // positions, padded layout
  const float *rx, *ry, *rz;  // rest positions, padded layout
  const int *du, *dv;
  const std::uint8_t* mixed;
  int count = 0;
  float range2 = 0;
  // The pairs in range (point indices, lower and upper end), in no set order: room for every point of the rows
  // asked for at every offset (count * W * rows)
  std::uint32_t *lower = nullptr, *upper = nullptr;
  // The tests a list's build rules out, passed over (CollisionPairs::stencilTiles): the grid in squares of `edge`
  // points, `across` of them a row of squares; active[t] has bit k set where offset k's pairs from square t's points
  // are tested (count <= 64), the others being out of range. Where record, every pair is tested and
  // min2[t * count + k] given the least squared distance of offset k's pairs from square t's points (+inf coming
  // in). active and min2 nullptr: every pair tested.
  int edge = 0, across = 0;
  const std::uint64_t* active = nullptr;
  float* min2 = nullptr;
  bool record = false;
  // Recording, row of squares number `shared_row` records into shared_min2 (across * count floats) instead: a row of
  // squares this thread shares with the one before it, which merges it (CollisionPairs::mergeSharedRecord). -1: none.
  int shared_row = -1;
  float* shared_min2 = nullptr;
};

// GridStencilArgs' squares for GridPath::stencilPairs (CollisionPairs::stencilTiles makes them): each thread of a
// team calls prepare(y0, y1) with its rows of points before its tests (the least distances cleared for a record, or
// the squares' offsets to test worked out). At a record, a thread whose first row is not a square's records that row
// of squares into shared_min2, for the thread before it to merge (CollisionPairs::mergeSharedRecord): prepare
// returns that row's number, else -1.
struct GridStencilTiles {
  int edge = 0, across = 0;
  const std::uint64_t* active = nullptr;
  float* min2 = nullptr;
  float* shared_min2 = nullptr;
  bool record = false;
  std::function<int(long long, long long)> prepare;
};

// The spheres and planes of a scene and the points they act on (collideObjects).
struct CollideArgs {
  float* x;              // positions, vec3 array seen as floats
  float* v;              // displacements (x - x_prev), the same
  const float* pinned;   // per point: all bits set where pinned
  const float* spheres;  // per sphere: centre x, y, z, radius, friction
  int sphere_count = 0;
  const float* planes;  // per plane: point x, y, z, unit normal x, y, z, friction
  int plane_count = 0;
  float plane_epsilon = 0, surface_offset = 0;  // physics::kPlaneEpsilon, kSurfaceOffset as float
};

// collideObjects on a grid path's padded arrays (GridPath): positions, displacements and pin masks per padded index.
struct CollideRowsArgs {
  CollideArgs objects;  // its spheres and planes (x, v and pinned unused)
  GridShape shape;
  float *x, *y, *z, *vx, *vy, *vz;
  const float* pinned;
};

// The self-collision lists' staleness test on a grid cloth (CollisionPairs::needsBuild): per square tile of
// edge x edge points (tiles in rows of `across`), the box of the displacements x - anchor and of the positions.
struct TileBoxArgs {
  const float *x, *anchor;  // vec3 arrays seen as floats
  int w = 0, h = 0, edge = 0, across = 0;
  float* out;            // per tile 12 floats: displacement min xyz, max xyz, position min xyz, max xyz
  int tv0 = 0, tv1 = 0;  // the rows of tiles [tv0, tv1) to box
  // Where given, the positions and the anchors in a grid path's padded layout, read instead of x and anchor
  // (no vec3 to split: about half the kernel's instructions)
  GridShape shape{};
  const float *px = nullptr, *py = nullptr, *pz = nullptr, *ax = nullptr, *ay = nullptr, *az = nullptr;
};

// The most tiles tilesMovedApart compares (CollisionPairs makes at most 16 x 16).
constexpr int kMaxCompareTiles = 256;
// CollisionPairs::compareTiles over `count` tiles' boxes as tileBoxes writes them: the tiles a taken from
// `first` in steps of `step`, each against every tile c >= a.
struct TileCompareArgs {
  const float* boxes;
  int count = 0, first = 0, step = 1;
  float apart2 = 0, limit2 = 0;   // the squares of compareTiles' apart and limit, computed as it does
  const std::atomic<bool>* stop;  // set by another thread that has found a pair: this one may stop
  // Where given, the pairs of tiles near and moved apart are written here (a, c with a <= c), up to `capacity`
  // of them, for the caller to look at more closely; the answer is true only beyond that many.
  std::uint32_t* found = nullptr;
  int capacity = 0;
  int* found_count = nullptr;
};

// One instruction set's kernels. Each works on the rows [y0, y1) of the grid (for a stretch colour, the
// rows where its springs start), so a team of threads can split a pass by rows.
struct GridKernels {
  const char* name;  // "sse2", "avx2", "avx512"
  int width;         // lanes
  // vec3 array <-> three padded arrays
  // signed_rows (or nullptr): set to 1 for each row with a coordinate that is -0, left as it is for the rest.
  void (*toSoa)(const GridShape&, const float* aos, float* x, float* y, float* z, int y0, int y1,
                std::uint8_t* signed_rows);
  void (*fromSoa)(const GridShape&, const float* x, const float* y, const float* z, float* aos, int y0, int y1);
  // Gravity and every enabled spring, summed per point in the adjacency's order (docs/design.md).
  void (*forces)(const GridForceArgs&, int y0, int y1);
  // Provot's stretch limit over the springs of colour 2 * direction + parity (core/colouring.hpp).
  void (*stretchColour)(const GridStretchArgs&, int direction, int parity, int y0, int y1);
  // One XPBD sweep's colour (physics::xpbdDistanceCorrection with the springs' multipliers, or 0 where
  // lambda is not kept), each spring's ends moved by -w_a p and +w_b p.
  void (*xpbdColour)(const GridStretchArgs&, int direction, int parity, int y0, int y1);
  // VBD's Newton steps (physics::vbdAddSpring over the adjacency's order, vbdStep) of points [first, last) of
  // args.points, a vector at a time by gathers: no two of them share a spring.
  void (*vbdPoints)(const GridVbdArgs&, long long first, long long last);
  // Verlet in displacement form (physics::integrateVerlet, then x += v) over vec3 arrays seen as floats,
  // [first, last) in floats: per float its point's inverse mass and pin mask (all bits set: pinned, which
  // keeps x and sets v to +0). Not grid-specific: it needs no neighbours.
  void (*integrate)(float* x, float* v, const float* f, const float* inv_mass3, const float* pinned3, float dt2,
                    float keep, long long first, long long last);
  // The same on rows [y0, y1) of the padded arrays (GridIntegrateArgs).
  void (*integrateRows)(const GridIntegrateArgs&, int y0, int y1);
  // Whether rows [y0, y1) pass the health check's quick look: every coordinate within the bound, every displacement
  // finite, every spring that starts there at most its limit long (a NaN passes none of them).
  bool (*healthyRows)(const GridHealthArgs&, int y0, int y1);
  // The entries k in [first, last) whose pair {owner[k], partner[k]} is within self-collision range, by the
  // test of physics::selfCollisionCorrection (a NaN distance counts, as there), with both ends' terms and cell
  // orders (PairTermOut), written to out in ascending k; their count returned. x is the vec3 array of `points`
  // seen as floats; inv_range: 1 / (2 thickness), the grid of cellOrder. Not grid-specific.
  int (*pairTerms)(const float* x, std::size_t points, const std::uint32_t* owner, const std::uint32_t* partner,
                   std::uint32_t first, std::uint32_t last, float thickness, float inv_range, PairTermOut* out);
  // Self-collision's stencil (cpu/collision_pairs.hpp) from the points of rows [y0, y1): the pairs whose partner
  // lies on the grid, is not held at rest, and is within range, written to lower and upper (see GridStencilArgs);
  // their count returned.
  int (*stencilPairs)(const GridStencilArgs&, int y0, int y1);
  // The slots s in [first, last) whose candidate is within reach of the point now (a NaN distance is not) and
  // not surely held or on the stencil by its offset: written to out in ascending order, their count returned.
  // What the build must look at pair by pair; a flat cloth's buckets hold almost none.
  int (*scanPairs)(const PairScanArgs&, std::uint32_t first, std::uint32_t last, std::uint32_t* out);
  // scanPairs for the points at slots [p0, p1) of the same arrays (PairScanArgs' px ... pv unused) against each of
  // `count` ranges of slots, each vector of candidates loaded once for all of them. Writes each pair found as its
  // point's slot to points and its candidate's to slots (with kFarSlot where it is far: the lane's squared distance,
  // as the list's part needs it, from the vector that had it), range by range, returns how many; whole vectors are
  // stored, so each array needs kPairScanPad words past the pairs. One call a cell: a cell holds a few points (2.7 on
  // CS184's selfCollision) and a range a few candidates, and a call a range cost 47 ns.
  int (*scanCell)(const PairScanArgs&, std::uint32_t p0, std::uint32_t p1, const CellRange* ranges, int count,
                  std::uint32_t* points, std::uint32_t* slots);
  // scanCell's pairs of slots, count of them, filed as the build keeps them: each slot's point, the pair passed over
  // where its offset lies in the box and is not the list's there (held at rest, or the stencil's), else written as
  // {lower, upper | far} to out[0] or out[1] (PairFileArgs::split), in the order given; how many to each in
  // counts. Whole vectors are stored: each output needs room for count + kPairScanPad pairs.
  void (*filePairs)(const PairFileArgs&, const std::uint32_t* points, const std::uint32_t* slots, int count,
                    FiledPair* const out[2], int counts[2]);
  // CpuSolver::collide on the points [first, last) without meshes: each sphere, then each plane, as
  // physics::collideSphere and collidePlane compute them, lane by lane. Returns where it stopped: the last
  // points, fewer than a vector, are the caller's.
  long long (*collideObjects)(const CollideArgs&, long long first, long long last);
  // collideObjects on rows [y0, y1) of the padded arrays, every point of them (no tail left to the caller).
  void (*collideRows)(const CollideRowsArgs&, int y0, int y1);
  // TileBoxArgs' boxes of the tiles in its rows; false if a displacement is not finite (the lists must be rebuilt).
  bool (*tileBoxes)(const TileBoxArgs&);
  // The box of the displacements of every point of rows [y0, y1), from TileBoxArgs' padded positions and anchors
  // (which it needs), into out: min x, y, z, max x, y, z; false if a displacement is not finite.
  bool (*displacementBox)(const TileBoxArgs&, int y0, int y1, float* out);
  // HashGrid<float>::cellOf of points [first, last) of x (vec3s) into cells (ivec3s), and box (least x, y, z, then
  // greatest cell; holding the box to widen, or INT_MAX and INT_MIN) widened to hold them
  void (*cellsOf)(const float* x, std::size_t first, std::size_t last, float inv_cell_size, int* cells, int* box);
  // Whether two tiles lie within apart of each other while the box of their displacements together has a
  // diagonal over limit (or not finite): compareTiles' test, several tiles c side by side.
  bool (*tilesMovedApart)(const TileCompareArgs&);
  // Probes of this machine's peak with these instructions (cpu/machine_peak.hpp); each returns a value that
  // depends on all its work, so that none of it can be left out. Independent chains, so throughput counts:
  // 6 multiplies and 6 adds per lane and rep (no fused multiply-add: the build forbids it)
  float (*probeAddMul)(long long reps);
  // 4 square roots and 4 divisions per lane and rep, the two operations every spring needs
  float (*probeDivSqrt)(long long reps);
  // STREAM's triad a = b + s c over n floats (n a multiple of the width): 12 bytes per element
  void (*probeTriad)(float* a, const float* b, const float* c, long long n, float s);
};

enum class GridIsa { Auto, Sse2, Avx2, Avx512 };

// The kernels for `isa`; Auto picks the widest the CPU has (checked at run time: the binary runs on any x86-64):
// AVX-512, else AVX2, else SSE2. Throws std::runtime_error for a set the CPU does not have.
const GridKernels& gridKernels(GridIsa isa = GridIsa::Auto);
bool cpuHasAvx2();
bool cpuHasAvx512();  // F, DQ and VL, the parts the kernels use

const GridKernels& gridKernelsSse2();
const GridKernels& gridKernelsAvx2();
const GridKernels& gridKernelsAvx512();

}  // namespace drape
