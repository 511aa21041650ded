// GPU buffer layouts (std430) and binding points, declared once for C++ and GLSL.
//
// C++ includes this through src/gpu/layout.hpp, which brings in glm and <cstdint> first: the GLSL
// loader resolves #include textually even inside #if blocks, so this file includes nothing itself.
// Only 4-byte scalars and vec4s appear in structs, so std430 and the C++ ABI agree without
// hidden padding (a vec3 is 16-byte aligned in std430 but 4-byte aligned in glm);
// tests/layout_test.cpp checks every size and offset.
#pragma once

#ifdef __cplusplus
namespace drape::gpu {
using glm::vec2;
using glm::vec4;
using uint = std::uint32_t;
#define DRAPE_CONSTANT(type, name, value) inline constexpr type name = value
#else
#define DRAPE_CONSTANT(type, name, value) const type name = value
#endif

// Shader storage binding points. Ping-pong passes read the *In buffers and write the *Out ones; the
// solver binds the two copies of the state to these points alternately.
DRAPE_CONSTANT(uint, kBindingParams, 0u);            // SimParams
DRAPE_CONSTANT(uint, kBindingPosIn, 1u);             // vec4 per point: xyz position (m), w pin flag
DRAPE_CONSTANT(uint, kBindingDispIn, 2u);            // 3 floats per point, packed: displacement x - x_prev (m)
DRAPE_CONSTANT(uint, kBindingPosOut, 3u);            // the other copy of positions, written by ping-pong passes
DRAPE_CONSTANT(uint, kBindingDispOut, 4u);           // the other copy of displacements
DRAPE_CONSTANT(uint, kBindingOffsets, 5u);           // uint per point + 1: CSR offsets into neighbours
DRAPE_CONSTANT(uint, kBindingNeighbors, 6u);         // Neighbor per adjacency entry
DRAPE_CONSTANT(uint, kBindingColliders, 7u);         // Collider: NUM_SPHERES spheres, then NUM_PLANES planes
DRAPE_CONSTANT(uint, kBindingGridPoints, 8u);        // GridPoint per point
DRAPE_CONSTANT(uint, kBindingGridCounts, 9u);        // uint per bucket: points counted into it (atomics); the
                                                     // lists' per-point candidate counts reuse it
DRAPE_CONSTANT(uint, kBindingGridStart, 10u);        // uint per bucket + 1: exclusive prefix sum of counts
DRAPE_CONSTANT(uint, kBindingGridBlocks, 11u);       // uint per scan block: block totals, then their prefix
DRAPE_CONSTANT(uint, kBindingGridScatter, 12u);      // uint per point: indices by bucket, in atomic order
DRAPE_CONSTANT(uint, kBindingGridSorted, 13u);       // GridEntry per point: by bucket, ascending index within
DRAPE_CONSTANT(uint, kBindingHealth, 14u);           // Health
DRAPE_CONSTANT(uint, kBindingPick, 15u);             // PickResult
DRAPE_CONSTANT(uint, kBindingColouredSprings, 16u);  // ColouredSpring, grouped by colour (Gauss-Seidel stretch)
DRAPE_CONSTANT(uint, kBindingPairControl, 17u);      // PairControl: the self-collision lists' bookkeeping
DRAPE_CONSTANT(uint, kBindingPairAnchor, 18u);       // vec4 per point: position at the last list build
DRAPE_CONSTANT(uint, kBindingPairStart, 19u);        // uint per point + 1: where each point's list starts
DRAPE_CONSTANT(uint, kBindingPairList, 20u);         // uint per candidate: each point's candidates, ascending
// Per-point quantities that a mesh cloth does not share between its points (a grid's are all alike).
DRAPE_CONSTANT(uint, kBindingPointMass, 21u);   // PointMass per point
DRAPE_CONSTANT(uint, kBindingXpbdLambda, 22u);  // float per coloured spring: XPBD multipliers (iterations > 1)
// The one-dispatch path (glsl/sim/one_group.comp): per spring colour and point, the point's spring of
// that colour, if any (ColourPartner, colour-major).
DRAPE_CONSTANT(uint, kBindingColourPartners, 23u);
DRAPE_CONSTANT(uint, kBindingTethers, 24u);  // Tether per point and slot (TETHER_SLOTS a point), point-major
// Vertex Block Descent: the points grouped by colour (core/colouring.hpp), and with more than one sweep
// per substep the prediction y each point's inertia pulls towards.
DRAPE_CONSTANT(uint, kBindingColouredPoints, 25u);  // uint per point: point indices grouped by colour
DRAPE_CONSTANT(uint, kBindingVbdInertia, 26u);      // vec4 per point: xyz the prediction y (iterations > 1)
// Self-collision with pairs held at rest (HELD_AT_REST): 3 floats per point, packed, the rest positions.
DRAPE_CONSTANT(uint, kBindingRest, 27u);
// The face contacts (collide_faces.comp): uints, the layout below (kFace*); vec4s, each mesh's grid constants
// and features.
DRAPE_CONSTANT(uint, kBindingFaceTable, 28u);
DRAPE_CONSTANT(uint, kBindingFaceFeatures, 29u);
DRAPE_CONSTANT(uint, kBindingCount, 30u);  // binding points used: one more than the largest

// Work-group sizes, shared so C++ computes group counts from the same numbers.
DRAPE_CONSTANT(uint, kLocalSize, 128u);      // per-point and per-bucket kernels
DRAPE_CONSTANT(uint, kScanLocalSize, 256u);  // prefix-sum kernels
DRAPE_CONSTANT(uint, kScanItems, 16u);       // consecutive buckets summed by one scan invocation
DRAPE_CONSTANT(uint, kScanBlock, 4096u);     // kScanLocalSize * kScanItems buckets per scan work group

// The indirect dispatches of the self-collision list build (PairDispatch, 3 uints each).
DRAPE_CONSTANT(uint, kPairDispatchPoints, 0u);       // one invocation per point (kLocalSize groups, 2D if large)
DRAPE_CONSTANT(uint, kPairDispatchOne, 1u);          // one work group
DRAPE_CONSTANT(uint, kPairDispatchGridBlocks, 2u);   // one work group per kScanBlock buckets
DRAPE_CONSTANT(uint, kPairDispatchPointBlocks, 3u);  // one work group per kScanBlock points
DRAPE_CONSTANT(uint, kPairDispatchCount, 4u);

// The phases of a substep the one-dispatch kernel runs (glsl/sim/one_group.comp's u_phases): a frame runs them
// all, a stage function of the solver one (GpuPlan says which).
DRAPE_CONSTANT(uint, kPhaseIntegrate, 1u);     // forces + integrate (+ collide, where the plan fuses it there)
DRAPE_CONSTANT(uint, kPhaseStretch, 2u);       // the stretch passes
DRAPE_CONSTANT(uint, kPhaseSelfCollide, 4u);   // self-collision (+ collide)
DRAPE_CONSTANT(uint, kPhaseTether, 8u);        // the tethers
DRAPE_CONSTANT(uint, kPhaseCollideLast, 16u);  // the collisions again, after the tethers and the stretch limit
DRAPE_CONSTANT(uint, kPhaseAll, 31u);

// The face contacts' table (gpu::faceTables): a header of kFaceHeaderWords, then kFaceMeshWords per mesh with
// a sharp feature, in scene order, then the arrays the header words point at (each a start in the table).
DRAPE_CONSTANT(uint, kFaceMeshes, 0u);          // meshes with a sharp feature
DRAPE_CONSTANT(uint, kFaceEdgeStart, 1u);       // per point + 1: where its edges start in point_edges
DRAPE_CONSTANT(uint, kFacePointEdges, 2u);      // edge indices, each point's ascending
DRAPE_CONSTANT(uint, kFaceEdges, 3u);           // 2 points an edge, the smaller first
DRAPE_CONSTANT(uint, kFaceTriangleStart, 4u);   // per point + 1: where its triangles start in point_triangles
DRAPE_CONSTANT(uint, kFacePointTriangles, 5u);  // triangle indices, each point's ascending
DRAPE_CONSTANT(uint, kFaceTriangles, 6u);       // 3 points a triangle (the topology's)
DRAPE_CONSTANT(uint, kFaceHeaderWords, 8u);
DRAPE_CONSTANT(uint, kFaceGridEdgeStart, 0u);  // a mesh's words: per grid cell + 1, into its grid edges
DRAPE_CONSTANT(uint, kFaceGridEdges, 1u);      // feature edge indices, each cell's ascending
DRAPE_CONSTANT(uint, kFaceGridCornerStart, 2u);
DRAPE_CONSTANT(uint, kFaceGridCorners, 3u);
DRAPE_CONSTANT(uint, kFaceGridDims, 4u);        // 3 words: the grid's cells along x, y, z
DRAPE_CONSTANT(uint, kFaceFeatureHeader, 7u);   // FaceFeatures index: (origin, 1 / cell), (thickness, 0, 0, 0)
DRAPE_CONSTANT(uint, kFaceFeatureEdges, 8u);    // FaceFeatures index of edge 0: 4 vec4s an edge
DRAPE_CONSTANT(uint, kFaceFeatureCorners, 9u);  // FaceFeatures index of corner 0: 2 vec4s a corner
DRAPE_CONSTANT(uint, kFaceMeshWords, 10u);

// Health flags (the blow-up check, src/core/health.hpp): raised by health.comp after a frame's last pass,
// read back on request. The same bits as drape::Health.
DRAPE_CONSTANT(uint, kHealthNonFinite, 1u);      // a position or displacement became NaN or infinite
DRAPE_CONSTANT(uint, kHealthOutOfBounds, 2u);    // a point left the sane box |x| <= SimParams.sane_bound
DRAPE_CONSTANT(uint, kHealthOverstretched, 4u);  // a spring longer than SimParams.blow_up_stretch x rest

// Everything a kernel needs that is not per point. Values are derived on the host with exactly the
// float operations the CPU reference uses (dt2 = dt * dt, ...), so both
// start every substep from bit-identical constants.
struct SimParams {
  vec4 stiffness;         // N/m per spring type: x structural, y shearing, z bending (0.2 ks); w unused
  vec4 wind_velocity;     // xyz: steady air velocity (m/s); w: turbulence (relative amplitude)
  vec4 weight;            // a grid's PointMass::weight, the same for every point (kernels with UNIFORM_MASS)
  float dt;               // s, one substep
  float dt2;              // s^2, dt * dt
  float keep;             // 1 - damping/100: fraction of the displacement kept per substep
  float thickness;        // m; self-collision range is 2 * thickness
  float inv_cell_size;    // 1/m, 1 / hash-grid cell edge (2 * thickness), rounded on the host
  float steps_per_frame;  // self-collision corrections are divided by this (CS184)
  float stretch_limit;    // springs are shortened to at most this times their rest length
  float noise_scale;      // m, wind noise wavelength
  float noise_speed;      // 1/s, wind noise drift
  float sane_bound;       // m, |x| beyond this on any axis is reported as a blow-up
  uint point_count;       // points in the cloth
  uint bucket_mask;       // hash-grid buckets - 1 (buckets are a power of two)
  uint bucket_count;      // hash-grid buckets
  uint scan_blocks;       // ceil(bucket_count / kScanBlock)
  float inv_pair_cell;    // 1/m, 1 / the list build's cell edge (pair_reach), rounded on the host
  float pair_reach;       // m, 2 * thickness + the list's margin: the build lists pairs closer than this
  float pair_reach2;      // m^2, pair_reach * pair_reach
  float pair_margin;      // m, the list's margin (skin)
  float blow_up_stretch;  // a spring longer than this times its rest length is reported as a blow-up
  uint pad0;              // std430 rounds the struct to 16 bytes; C++ must see the same size
  vec4 alpha_tilde;       // XPBD: compliance / dt^2 = 1 / (k dt^2) per spring type (xyz as stiffness); w unused
};

// One adjacency entry: the spring from this point to another, in the CPU's order (ascending spring
// index), holding only the spring types the scene enables. 8 bytes, because the adjacency is the
// largest buffer (about 12 entries per point: some 6 springs each, listed from both ends) and must fit
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
DRAPE_CONSTANT(uint, kNeighborIndexBits, 30u);          // the other point's index (cloths < 2^30 points)
DRAPE_CONSTANT(uint, kNeighborIndexMask, 0x3fffffffu);  // ... in the low bits of `index_type`
struct Neighbor {
  uint index_type;  // other point's index | SpringType (0 structural, 1 shearing, 2 bending) << kNeighborIndexBits
  float rest;       // m
};

// A spring of the Gauss-Seidel stretch pass (src/core/colouring.hpp): springs of one colour share no
// point, so one invocation per spring can move both ends in place.
struct ColouredSpring {
  uint a;      // end with the smaller index
  uint b;      // other end
  float rest;  // m
  uint type;   // SpringType: which of SimParams.alpha_tilde is the spring's (XPBD)
};

// A point's spring of one colour, seen from the point (the one-dispatch path's Gauss-Seidel stretch): springs
// of a colour share no point, so each point has at most one. 8 bytes.
DRAPE_CONSTANT(uint, kNoPartner, 0xffffffffu);
struct ColourPartner {
  uint other;  // the spring's other end; kNoPartner: the point has no spring of this colour
  float rest;  // m
};

// A point's tie to one of its nearest pins (src/core/tethers.hpp). 8 bytes.
DRAPE_CONSTANT(uint, kNoTether, 0xffffffffu);
struct Tether {
  uint anchor;  // the pinned point; kNoTether: an unused slot
  float rest;   // m, the distance to it along the cloth at rest
};

// What a point does not share with the others on a mesh cloth: its weight and inverse mass, and its wind
// drag times area, each rounded on the host with the CPU's operations (CpuSolver::refreshDerived); and the
// four points whose cross(x[b] - x[a], x[d] - x[c]) is its normal for wind (Topology::normal_stencil). One
// buffer, not two: Mesa allows a compute shader 16 storage blocks, and the integrate kernel with
// self-collision has 16.
struct PointMass {
  vec4 weight;  // xyz: gravity * mass (N); w: 1 / mass (1/kg)
  uint normal_a;
  uint normal_b;
  uint normal_c;
  uint normal_d;
  float drag_area;  // wind drag * the point's area (kg/m)
  uint pad0;
  uint pad1;
  uint pad2;
};

// A sphere (a = centre xyz, radius w; b.x = friction) or a plane (a = point xyz, friction w;
// b = unit normal xyz).
struct Collider {
  vec4 a;
  vec4 b;
};

// Self-collision candidate lists (src/cpu/collision_pairs.hpp on the CPU): built from the anchor
// positions, and valid while no point has moved sqrt(travel2) from its anchor.
struct PairState {
  uint stale;        // nonzero: some point moved too far since the last build (or no list yet)
  uint extent_bits;  // the build's largest |coordinate|, as float bits (they order like the floats)
  float travel2;     // m^2, squared safe travel of the last build; negative: no valid list
  uint total;        // entries the last build needed (pairStart[point_count])
  uint capacity;     // entries the list buffer holds (host); a point whose list does not fit is served
                     // from the grid instead (slower, same result)
  uint overflow;     // sticky: some build needed more than `capacity`
  uint builds;       // list builds so far
  uint pad0;
};

// Indirect dispatch arguments (x, y, z groups) of the list build: `live` is what the build passes
// dispatch, `full` the sizes the host computed; the prepare kernel copies full to live when the list
// is stale and zeroes live otherwise, so a fresh list costs no read-back.
struct PairDispatch {
  uint live[12];  // kPairDispatchCount * 3
  uint full[12];
};

// One buffer for both, also bound as GL_DISPATCH_INDIRECT_BUFFER: a storage block fewer per kernel.
struct PairControl {
  PairState state;
  PairDispatch dispatch;
};

// A slot of the hash grid's cell-ordered copy: the point's anchor and index. The list build scans a
// bucket's slots in order, so it reads contiguous memory, not a gather per candidate.
struct GridEntry {
  float x;  // m, the anchor (the position the grid was built from)
  float y;
  float z;
  uint index;  // the point
};

// A point's hash-grid cell and bucket, written by the grid count.
struct GridPoint {
  int cell_x;
  int cell_y;
  int cell_z;
  uint bucket;   // hashCell(cell) & bucket_mask
  uint arrival;  // position among the bucket's points in atomic (thread-timing) order
};

struct Health {
  uint flags;        // kHealth* bits
  uint first_point;  // smallest index of a point that raised a flag (0xffffffff: none)
  uint pad0;
  uint pad1;
};

// Ray picking: the smallest ray parameter among points within the pick radius (as float bits,
// which order like the floats for t >= 0), then the smallest index at that parameter.
struct PickResult {
  uint best_t_bits;  // 0xffffffff: nothing within the radius
  uint index;        // 0xffffffff: nothing within the radius
  uint pad0;
  uint pad1;
};

#ifdef __cplusplus
}  // namespace drape::gpu
#endif
#undef DRAPE_CONSTANT
