// The GPU solver's plan: what a substep and a frame dispatch, as a plain value worked out without a GL context
// by one pure function (makePlan) from the scene, the cloth's counts, the path asked for and the device's
// limits. GpuSolver only runs it (plan_runner.hpp); passes(), the -v listing, the dispatch counts and the
// traffic model (traffic.hpp) read it; tests/gpu_plan_test.cpp checks it without GL, and
// tests/gpu_solver_gl_test.cpp holds the dispatches really issued against it. docs/design.md section 4 has the
// table of passes and the list of what to touch to add one.
#pragma once

#include "core/colouring.hpp"
#include "core/scene.hpp"
#include "gpu/path_choice.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace drape::gpu {

// Every kernel dispatch the solver knows, in the order the bench lists their timings. Each has one row in
// the kernel table (kernels.hpp); a pass without one fails to compile there.
enum class Pass : std::uint8_t {
  ForcesIntegrate,
  ForcesIntegrateTiled,
  PairsCheck,
  PairsPrepare,
  PairsGridCount,
  GridBuild,
  GridScan,
  GridScanBlocks,
  GridScanOffsets,
  GridScatter,
  GridRank,
  PairsCount,
  PairsScan,
  PairsScanBlocks,
  PairsScanOffsets,
  PairsFill,
  SelfCollide,
  LimitStretch,
  LimitStretchColoured,
  LimitStretchTiled,
  LimitStretchForcesTiled,
  OneGroup,
  XpbdColoured,
  VbdColoured,
  Collide,
  Tether,
  CollideFaces,
  Pick,
  Health,
  Count
};
inline constexpr std::size_t kPassCount = std::size_t(Pass::Count);

// The solver's stage functions (forcesIntegrate(), selfCollide(), ...) run one stage of a substep; Health is
// the frame's check. CollideLast: the collisions again after the tethers and the stretch limit; Faces: the face
// contacts (with the collisions again after them).
enum class Stage : std::uint8_t {
  Integrate,
  Xpbd,
  Vbd,
  Collide,
  SelfCollide,
  Tether,
  Stretch,
  Faces,
  CollideLast,
  Health
};

// How many work groups a dispatch runs.
enum class Extent : std::uint8_t {
  Points,    // an invocation per point, kLocalSize a group
  One,       // one work group
  Indirect,  // the groups pairs_prepare wrote into PairDispatch command `command` (zero while the lists are fresh)
  Range,     // an invocation per element of [first, first + count): one colour's springs or points
  Tiles,     // a work group per block of `tile` x `tile` points
};

struct Dispatch {
  Pass pass = Pass::Count;
  Stage stage = Stage::Integrate;
  Extent extent = Extent::Points;
  bool ping_pong = false;              // reads one copy of the state and writes the other, which then is current
  std::uint32_t command = 0;           // Indirect
  std::uint32_t first = 0, count = 0;  // Range
  std::uint32_t tile = 0;              // Tiles: the block's edge
  std::uint32_t sweep = 0;             // xpbd_colour, vbd_colour: the sweep of the substep (0 starts it)
  std::uint32_t substeps = 0;          // one_group: the substeps it runs (u_substeps)
  std::uint32_t phases = 0;            // one_group: the kPhase* bits of each substep (u_phases)
  bool check_health = false;           // one_group: ends with the health check of the last state
  bool stretch_first = true;           // limit_stretch_forces_tiled: false for a frame's first (nothing to stretch)
  bool writes_commands = false;        // a later dispatch reads its indirect arguments (command barrier)
  bool checks_travel = false;          // checks, for the lists, how far the points moved (pairs_check fused)
  int advances = 0;                    // substeps completed after it: the wind's time moves on
};

// A frame (stepFrame()): `substep` `repeats` times, then `tail` once. On the one-dispatch path the substep is
// the frame's one dispatch, repeated once; elsewhere `repeats` is steps_per_frame and the tail ends with the
// health check.
struct FramePlan {
  std::vector<Dispatch> substep;
  int repeats = 0;
  std::vector<Dispatch> tail;
};

// One phase of the one-dispatch kernel's substep, as passes() lists it.
struct GroupPhase {
  std::uint32_t phase = 0;  // kPhase*
  std::string name;         // "in-group " and the general path's pass whose phase it runs
};

// The list build's shape: buckets and prefix-sum blocks (one work group up to kScanBlock).
struct ListLayout {
  std::uint32_t buckets = 0;            // hash buckets, a power of two
  std::uint32_t scan_blocks = 0;        // of buckets
  std::uint32_t point_scan_blocks = 0;  // of the lists' per-point counts
};

// The cloth's counts the plan and the traffic model depend on, kept by the device cloth (device_cloth.hpp).
struct ClothCounts {
  std::vector<std::uint32_t> colour_start;        // enabled coloured springs: colour c is [start[c], start[c + 1])
  std::vector<std::uint32_t> point_colour_start;  // VBD's point colours (empty until a scene asks for VBD)
  std::uint64_t adjacency_entries = 0;            // enabled springs seen from both ends
  int tether_slots = 0;                           // anchors a point (0: no tethers built, or no pins)
  int face_meshes = 0;                            // meshes with sharp features (gpu::faceTables)
  bool held_pairs = false;  // some pair may be held at rest at the thickness (self-collision's HELD_AT_REST)
};

struct PlanInput {
  const Scene& scene;
  const Topology& topo;
  const SpringColouring& colouring;
  const ClothCounts& counts;
  GpuPath path = GpuPath::Auto;
  DeviceLimits device;
  std::uint32_t buckets = 0;  // GpuSolverOptions::buckets (0: derived from the point count)
  int terms_held = 0;         // self-collision terms held in registers (GpuSolverOptions::self_terms_held, chosen)
};

struct Plan {
  SceneNeeds needs;
  PathChoice path;
  ListLayout lists;
  int points = 0, width = 0, height = 0;  // width, height: a grid's points along x and y
  int colours = 0;                        // spring colours of the colouring
  int tether_slots = 0;                   // anchors a point where tethers run, else 0
  int terms_held = 0;
  double dt = 0;                         // s, a substep in double (the wind's time)
  std::vector<Dispatch> substep;         // step(): one substep
  FramePlan frame;                       // stepFrame()
  std::vector<Dispatch> travel_check;    // selfCollide() on a state no forces+integrate checked: pairs_check
  std::vector<GroupPhase> group_phases;  // the one-dispatch path: its substep's phases, as listed
};

Plan makePlan(const PlanInput& in);

// What a stage function runs: the stage's dispatches of a substep, or its phase of the one-dispatch kernel.
// `travel_checked`: the current positions' travel was checked by a forces+integrate.
std::vector<Dispatch> stageDispatches(const Plan& plan, Stage stage, bool travel_checked);

// The listings and counts the Solver interface reports (docs/design.md section 4).
std::vector<std::string> substepListing(const Plan& plan);  // passes()
std::vector<std::string> frameListing(const Plan& plan);    // framePasses()
int dispatchesPerFrame(const Plan& plan);
double dispatchesPerSubstep(const Plan& plan);

// Buckets and scan blocks of the self-collision lists' build for `points` points.
ListLayout listLayout(std::uint64_t points, std::uint32_t buckets);

// Work groups of kLocalSize covering `invocations`, spread over y when x alone would pass `max_groups_x` (the
// kernels fold the 2D index back, see globalIndex() in glsl/sim/common.glsl).
glm::uvec3 groupsFor(std::uint64_t invocations, std::uint32_t max_groups_x);

}  // namespace drape::gpu
