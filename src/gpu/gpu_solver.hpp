// GPU solver: the passes of docs/design.md section 2 as OpenGL 4.5 compute kernels over SSBOs
// (glsl/sim/*.comp), compiled per scene with #defines, fused where the data flow allows, and
// consistent with CpuSolver<float> (tests/gpu_*_gl_test.cpp). Needs a current GL 4.5 context.
//
// One substep is this list of dispatches (a pass with nothing to do is not dispatched):
//   forces+integrate[+collide | +pairs_check]  per point: gather springs (+ wind), Verlet, then the
//                                               point's collisions, or, when a self-collision pass comes
//                                               next, whether it moved too far for the candidate lists
//   forces_tiled+integrate[...]                 the same on the tiled path for a flat grid without wind:
//                                               blocks in shared memory, springs by grid offset
//   pairs_prepare                               one invocation: switches the list build below on or off
//   pairs_grid_count ... pairs_fill             the candidate lists' build (glsl/sim/pairs.glsl), indirect
//                                               dispatches of zero work groups unless the lists are stale:
//                                               hash-grid count, grid_build (one work group up to 4096
//                                               buckets, else grid_scan grid_scan_blocks grid_scan_offsets
//                                               grid_scatter grid_rank), pairs_count, pairs_scan (or
//                                               pairs_scan pairs_scan_blocks pairs_scan_offsets beyond
//                                               4096 points), pairs_fill
//   self_collide[+collide]                      Jacobi self-collision over the lists, then the point's
//                                               collisions
//   limit_stretch_colour                        Gauss-Seidel stretch scheme: one dispatch per spring colour
//                                               and stretch pass, each moving both ends of its springs in place
//   limit_stretch_tiled                         or, on a grid cloth, every colour and pass in one dispatch of
//                                               blocks that each copy themselves and a ring around them into
//                                               shared memory (GpuPath::Tiled)
//   limit_stretch                               Jacobi stretch scheme: once per stretch pass
// With simulation.integrator xpbd or vbd, forces+integrate is the prediction (no springs, nothing fused), then
//   xpbd_colour                                 XPBD: one dispatch per spring colour and sweep, the springs
//                                               as distance constraints, both ends moved in place
//   vbd_colour                                  VBD: one dispatch per point colour and sweep, each point
//                                               of the colour moved in place by its Newton step
//   pairs_check                                 the lists' travel check (self-collision), or
//   collide                                     the points' collisions (no self-collision)
// before self-collision and the stretch limit as above.
// and once per frame, after the last substep (stepFrame()):
//   health                                      the blow-up check of core/health.hpp, writing only its flags
// Every pass that reads other points' positions reads one copy of the state and writes the other
// (Jacobi / ping-pong), so no invocation sees a neighbour's half-finished update.
#pragma once

#include "core/colouring.hpp"
#include "core/derived.hpp"
#include "core/health.hpp"
#include "core/solver.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "gl/shader_source.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

namespace gpu {
struct PairState;  // glsl/shared/layout.h
}

// How a substep is dispatched. General: the plan of dispatches above, any cloth, the Gauss-Seidel stretch
// limit one dispatch per colour. Tiled: the same plan with the stretch limit's colours and passes in one
// dispatch of blocks in shared memory (glsl/sim/limit_stretch_tiled.comp), for grid cloths whose colouring
// reaches few enough points for a block and its ring to fit. OneDispatch: every substep of a frame in one
// work group with the positions (and the self-collision grid) in shared memory (glsl/sim/one_group.comp),
// for cloths that fit it. Auto: OneDispatch where it fits, else Tiled where it applies, on a hardware GPU;
// on a software renderer (llvmpipe) the general path, which spreads a frame over its threads where one
// work group runs on one (measured in README.md, "GPU paths").
enum class GpuPath { Auto, General, Tiled, OneDispatch };

struct GpuSolverOptions {
  GpuPath path = GpuPath::Auto;
  std::uint32_t buckets = 0;         // self-collision hash buckets, a power of two; 0: one per point, as the CPU grid
  bool timing = false;               // time every pass (GL timer queries; else glFinish + wall clock, which stalls)
  HealthLimits health{};             // what health() reports as a blow-up
  std::size_t max_buffer_bytes = 0;  // largest buffer allowed; 0: GL_MAX_SHADER_STORAGE_BLOCK_SIZE
  double pair_margin = kDefaultPairMargin;  // self-collision list skin / (2*thickness), as CpuSolverOptions
  std::size_t pair_capacity = 0;            // list entries the buffer holds at first; 0: estimated from the cloth
  // Nonzero terms of a point's self-collision sum kept in registers while its list is swept once; a
  // point with more sums them by sweeping its list again per cell order (same bits, more gathers). -1:
  // chosen per device, 8 on a hardware GPU, 0 on a software renderer, where a gather is a cached load and
  // holding the terms costs more than it saves (README, "Self-collision on the GPU"). At most 32.
  int self_terms_held = -1;
};

// The scene needs more than the GPU allows (buffer size, work groups, memory). Thrown before any
// dispatch, with the sizes involved.
class GpuLimitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The self-collision candidate lists as the GPU built them, read back for tests and the bench.
struct GpuPairs {
  std::vector<std::uint32_t> start;  // point count + 1: point i's candidates are list[start[i] .. start[i+1])
  std::vector<std::uint32_t> list;   // ascending within each point (as far as `capacity` holds them)
  std::uint32_t capacity = 0;        // entries the buffer holds
  std::uint32_t builds = 0;          // list builds so far
  bool overflow = false;             // some build needed more than the capacity
  float travel2 = 0;                 // m^2, the last build's squared safe travel
};

// The hash grid as the GPU built it (from the anchor positions of the last list build), read back for tests.
struct GpuGrid {
  std::vector<glm::ivec3> cells;         // per point
  std::vector<std::uint32_t> buckets;    // per point: hashCell(cell) & (bucket count - 1)
  std::vector<std::uint32_t> arrival;    // per point: its slot in the bucket's atomic (thread-timing) order
  std::vector<std::uint32_t> start;      // bucket count + 1 prefix sums
  std::vector<std::uint32_t> sorted;     // point indices grouped by bucket, ascending within one
  std::vector<glm::vec3> sorted_anchor;  // per slot: the copy of sorted[slot]'s anchor
};

class GpuSolver final : public Solver {
 public:
  // Uses the current context. `context`, when not empty, is owned by the solver and outlives its GL
  // objects. Throws GpuLimitError before allocating anything when the scene does not fit,
  // gl::ShaderError when a kernel does not compile.
  explicit GpuSolver(Scene scene, GpuSolverOptions options = {}, gl::HeadlessContext context = {});
  ~GpuSolver() override;
  GpuSolver(const GpuSolver&) = delete;
  GpuSolver& operator=(const GpuSolver&) = delete;

  // "gpu", or the forced path's name ("gpu-general", "gpu-tiled", "gpu-onedispatch"), as the solver
  // factory calls them.
  std::string name() const override {
    return options_.path == GpuPath::General       ? "gpu-general"
           : options_.path == GpuPath::Tiled       ? "gpu-tiled"
           : options_.path == GpuPath::OneDispatch ? "gpu-onedispatch"
                                                   : "gpu";
  }
  const Scene& scene() const override { return scene_; }
  const Topology& topology() const override { return topo_; }

  void step() override;
  void stepFrame() override;  // one dispatch on the one-dispatch path, else Solver::stepFrame
  void reset() override;
  void setParams(const ClothSpec& cloth, const SimParams& sim) override;
  std::vector<glm::dvec3> readPositions() override;
  std::vector<glm::dvec3> readDisplacements() override;
  long long substeps() const override { return substeps_; }
  std::vector<std::string> passes() const override;
  // The one-dispatch path checks health inside its dispatch.
  std::vector<std::string> framePasses() const override {
    if (one_group_) return {};
    std::vector<std::string> out;
    for (const PlannedDispatch& d : frame_.tail)
      out.push_back(passName(d.pass));
    out.push_back(passName(kHealth));
    return out;
  }
  int dispatchesPerFrame() const override;
  double dispatchesPerSubstep() const override;
  // Whether this scene runs on the one-dispatch path (GpuPath), and, when it cannot, why not ("" if it can).
  bool oneDispatch() const { return one_group_; }
  std::string oneDispatchMisfit() const;
  // Whether the stretch limit runs as one tiled dispatch a substep (GpuPath), and, when it cannot, why not.
  bool tiledStretch() const { return tiled_; }
  // Whether it finds each point's springs from the grid (every direction's rests alike), not the table.
  bool tiledFromGrid() const { return tiled_ && !grid_rests_.empty(); }
  std::string tiledStretchMisfit() const;
  // The tiled kernel's block edge and ring width in points, and its invocations; all 0 when it does not apply.
  struct StretchTiling {
    std::uint32_t tile = 0, halo = 0, group_size = 0;
    std::uint32_t forces_tile = 0, forces_group_size = 0;  // forces_integrate_tiled.comp's (ring 2)
    std::uint32_t fused_tile = 0;  // limit_stretch_forces_tiled.comp's: the same copy, a ring of halo + 2
  };
  StretchTiling stretchTiling() const;
  // The tiling for a device with `shared` bytes of shared memory a work group and `max_group` invocations,
  // for a colouring that reaches `reach` points.
  static StretchTiling tilingFor(std::uint64_t shared, std::uint64_t max_group, int reach);
  // The fused kernel's traffic model per point of a W x H grid (bytesPerPointPerSubstep() counts it).
  static double fusedBytesPerPoint(int W, int H, const StretchTiling& tiling);
  // Whether stepFrame() fuses each substep's stretch limit with the next substep's forces, integration
  // and collisions (limit_stretch_forces_tiled.comp): one dispatch a substep, then the last substep's
  // stretch limit. On the tiled path, with the forces tiled, without self-collision or tethers. step()
  // alone, which must end on a whole substep, still runs the two kernels.
  bool fusedFrame() const { return fused_frame_; }
  std::vector<PassTiming> timings() const override;
  void resetTimings() override;

  // The stages of step(), public so tests can run each on a chosen state and compare it with the CPU
  // passes it fuses.
  void forcesIntegrate();  // CpuSolver accumulateForces + integrate (+ collide when there is no self-collision)
  void selfCollide();      // CpuSolver selfCollide (+ collide): hash grid, then the Jacobi correction
  void limitStretch();     // CpuSolver limitStretch: sim.stretch_passes dispatches
  void solveXpbd();        // CpuSolver solveXpbd: sim.iterations sweeps of one dispatch per colour (XPBD only)
  void solveVbd();         // CpuSolver solveVbd: sim.iterations sweeps of one dispatch per point colour (VBD only)
  void collide();          // CpuSolver collide, XPBD/VBD without self-collision (else it is fused, see below)
  void tether();           // CpuSolver tether: the long-range attachments, when the scene has them and pins
  bool usesTethers() const { return scene_.sim.tethers && tether_slots_ > 0; }
  bool collideFusedWithIntegrate() const { return !scene_.sim.self_collision && !isImplicit(scene_.sim.integrator); }
  // Replaces the state (positions, displacements) and the substep count (wind depends on time), as
  // CpuSolver::setState; pin flags stay.
  void uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, long long substeps);
  GpuGrid readGrid();    // after selfCollide(): the grid of the last list build
  GpuPairs readPairs();  // after selfCollide(): the lists it used

  // For the renderer. The state lives in two buffers that passes alternate between, so ask for the
  // current one every frame. vec4 per point (std430): xyz position, w the pin flag (1 pinned or held).
  const gl::Buffer& positionBuffer() const { return state_[current_].position; }
  const gl::Buffer& normalBuffer() const { return normals_; }    // vec4: unit normal, w = 0
  const gl::Buffer& tangentBuffer() const { return tangents_; }  // vec4: unit tangent (+u), w = bitangent sign
  const gl::Buffer& healthBuffer() const { return health_; }     // gpu::Health: the flags the health pass raised
  void computeNormals();  // once per frame before drawing: area-weighted normals, tangents from UVs

  // Mouse dragging. setPosition moves a point and keeps its displacement (x_prev moves with it, so no
  // velocity kick); a held point behaves as pinned at the target until releasePoint().
  void setPosition(std::uint32_t index, glm::vec3 position);
  void holdPoint(int index, glm::vec3 target);
  void releasePoint();
  // On the GPU: the point within `radius` of the ray nearest to its origin (smallest t >= 0, ties to the
  // smallest index), -1 if none. One explicit read-back of a few bytes.
  int pickPoint(glm::vec3 origin, glm::vec3 direction, float radius);

  // The flags raised since the last clearHealth() (reset() clears them). A state that was stepped or
  // replaced since the last check (step() without stepFrame(), uploadState()) is checked first, so the
  // answer is always about the current state. One read-back of a few bytes: it waits for the GPU.
  Health health() override;
  // No wait in the steady state: each frame's health pass is followed by a GPU copy of its flags (and
  // of the list build's overflow) into a persistently mapped ring and a fence; this reads the newest
  // slot whose fence has signalled, waiting only for the frame before the newest if even that one is
  // still running. A list overflow it finds grows the list buffer, as health() does.
  Health recentHealth() override;
  void clearHealth();
  void checkHealth();      // the health pass on the current state, as stepFrame() runs it after the last substep
  void finish() override;  // glFinish
  bool timesPasses() const { return options_.timing; }
  // The model: what each planned dispatch's kernel reads and writes of the buffers, from their layouts
  // and the cloth's counts (adjacency entries per point, springs per colour, candidates per point as the
  // last health read saw them), every gather counted as a full read (no cache) and data every point
  // shares (parameters, colliders) not counted. A substep whose lists are fresh (most: the build runs
  // zero work groups) moves no list-build bytes, so none are counted.
  double bytesPerPointPerSubstep() const override;
  long long deviceMemoryBytes() const override;  // all buffers this solver allocated
  // The #defines the scene's kernels were compiled with (NUM_SPHERES, NUM_PLANES, SELF_COLLISION, WIND,
  // UNIFORM_MASS).
  const gl::Defines& defines() const { return defines_; }
  // `d` and where the collisions and the lists' travel check run (the kernels' COLLIDE_AFTER_*, TRAVEL_CHECK).
  gl::Defines withFusion(gl::Defines d) const;
  const gl::ContextInfo& contextInfo() const { return context_info_; }

 private:
  enum PassId {
    kForcesIntegrate,
    kForcesIntegrateTiled,
    kPairsCheck,
    kPairsPrepare,
    kPairsGridCount,
    kGridBuild,
    kGridScan,
    kGridScanBlocks,
    kGridScanOffsets,
    kGridScatter,
    kGridRank,
    kPairsCount,
    kPairsScan,
    kPairsScanBlocks,
    kPairsScanOffsets,
    kPairsFill,
    kSelfCollide,
    kLimitStretch,
    kLimitStretchColoured,
    kLimitStretchTiled,
    kLimitStretchForcesTiled,
    kOneGroup,
    kXpbdColoured,
    kVbdColoured,
    kCollide,
    kTether,
    kNormals,
    kPick,
    kHealth,
    kPassCount
  };
  enum class Stage { Integrate, Xpbd, Vbd, Collide, SelfCollide, Tether, Stretch };
  // One dispatch of the substep. The plan is worked out once per scene (buildPlan(), again after a live
  // parameter change): step() runs it, and stepFrame() the frame plan made from it (frame_), which
  // passes() lists (the -v listing and the bench print that) and tests/gpu_solver_gl_test.cpp holds
  // against the dispatches really issued.
  struct PlannedDispatch {
    enum class Size { Points, One, Indirect, Springs, ColourPoints, Tiles };
    PassId pass;
    Stage stage;
    const gl::Program* program;
    Size size;
    bool ping_pong;                      // reads one copy of the state and writes the other, which then is current
    std::uint32_t command = 0;           // Indirect: the PairDispatch command pairs_prepare wrote
    std::uint32_t first = 0, count = 0;  // Springs, ColourPoints: one colour's range of the coloured springs or points
    std::uint32_t sweep = 0;             // xpbd_colour, vbd_colour: which sweep of the substep (0 starts it)
    bool writes_commands = false;        // a later dispatch reads its indirect arguments (command barrier)
    bool unless_checked = false;         // only when forces+integrate has not checked the travel (a stage run alone)
  };
  struct StateBuffers {
    gl::Buffer position;      // vec4 per point, w = pin flag
    gl::Buffer displacement;  // 3 floats per point, packed (glm::vec3)
  };
  // A kernel specialised for the chosen path, with the defines it was compiled with: a new choice (after a
  // live parameter change) recompiles it only when they change.
  struct PathProgram {
    gl::Program program;
    gl::Defines defines;
    void compile(const char* file, const gl::Defines& with);
  };
  struct Programs {
    gl::Program forces_integrate, self_collide;
    gl::Program pairs_check, pairs_prepare, pairs_grid_count, pairs_count, pairs_scan[3], pairs_fill;
    gl::Program grid_build, grid_scan[3], grid_scatter, grid_rank;
    gl::Program limit_stretch, limit_stretch_coloured;
    PathProgram limit_stretch_tiled;         // the tiled path, compiled when it is chosen
    PathProgram forces_integrate_tiled;      // ... and its forces, where the scene allows them
    PathProgram limit_stretch_forces_tiled;  // ... and both fused, where stepFrame() fuses them (fusedFrame())
    PathProgram one_group;                   // the one-dispatch path, compiled when it is chosen
    gl::Program xpbd_coloured, collide;      // XPBD only (collide: VBD too)
    gl::Program vbd_coloured;                // VBD only
    gl::Program tether;                      // compiled when the scene first asks for tethers
    gl::Program health;
    gl::Program normals, pick[2];  // compiled on first use
  };
  struct PendingQuery {
    PassId pass;  // the pass that ended at this timestamp; kPassCount: a start
    gl::Query query;
  };

  void buildPlan();                    // plan_, then frame_ from it
  void planSubstep();                  // plan_
  void choosePath(bool constructing);  // GpuSolverOptions::path for this scene: one_group_, its kernel and table
  void uploadColourPartners();
  void setPathUniforms() const;                 // the chosen path's programs' uniforms that stay until the next choice
  std::vector<float> uniformGridRests() const;  // grid_rests_ as it should be; empty where rests differ
  std::string tiledStretchMisfit(const StretchTiling& tiling) const;  // tiledStretchMisfit() for a worked-out tiling
  std::uint32_t oneGroupSize() const;                                 // the one-dispatch kernel's invocations
  std::uint32_t oneGroupBuckets() const;                              // its in-group self-collision grid's buckets
  // The one-dispatch kernel: `substeps` substeps of the phases in `phases` (bit 0 forces + integrate
  // (+ collide), bit 1 the stretch passes).
  // With `check_health`, the health check of health.comp on the last state, in the same dispatch.
  void runOneGroup(std::uint32_t substeps, std::uint32_t phases, bool check_health);
  double bytesPerPoint(const PlannedDispatch& d) const;
  // A tiled kernel's blocks of `tile` along an edge of `points`, and the points they copy along it with
  // rings of `ring` (clipped to the cloth).
  static std::uint32_t tileCount(int points, std::uint32_t tile);
  static std::uint64_t copiedPoints(int points, std::uint32_t tile, std::uint32_t ring);
  static double copiedPerPoint(int W, int H, std::uint32_t tile, std::uint32_t ring);
  bool tiledForces() const;  // the tiled path gathers forces by grid offset too (forces_integrate_tiled.comp)
  void runStage(Stage stage);
  void runStageOrPhase(Stage stage, std::uint32_t phase);  // the stage's dispatches, or its one-dispatch phase
  void run(const PlannedDispatch& d);
  void checkLimits() const;
  void allocate();
  void allocateGrid();
  void allocateLambda();
  void allocateVbd();      // the first time the scene asks for VBD: the point colouring; y with iterations > 1
  void allocateTethers();  // the first time the scene asks for them: anchors on the CPU, the buffer, the kernel
  void uploadParams();
  void uploadAdjacency();
  gl::Defines sceneDefines() const;
  bool uniformMass() const { return scene_.cloth.isGrid(); }
  bool hasColliders() const {
    return !scene_.spheres.empty() || !scene_.planes.empty() || !scene_.meshes.empty();
  }  // every point's PointMass::weight is alike
  void compilePrograms();
  std::string passName(PassId pass) const;
  std::uint64_t maxBufferBytes() const;  // GpuSolverOptions::max_buffer_bytes, else GL_MAX_SHADER_STORAGE_BLOCK_SIZE
  std::uint32_t bucketCount() const;
  std::uint32_t scanBlocks() const;
  std::uint32_t pointScanBlocks() const;
  bool gridInOneGroup() const;
  std::uint64_t pairCapacityEstimate() const;
  void allocatePairList(std::uint64_t capacity);
  void invalidatePairs();

  void bindShared() const;
  void bindState(int in, int out) const;
  glm::uvec3 groupsFor(std::uint64_t invocations, std::uint32_t local_size) const;
  // Runs one dispatch (timed when timing is on) followed by the storage barrier the next pass needs.
  void dispatch(PassId pass, const gl::Program& program, glm::uvec3 groups);
  // The same with the group counts of PairDispatch command `command`, written on the GPU.
  void dispatchIndirect(PassId pass, const gl::Program& program, std::uint32_t command);
  template <class F>
  void timed(PassId pass, F&& run);
  gl::Query takeQuery();  // a timestamp query, recorded now
  // Adds up the pass times of the timestamps the GPU has written; with `wait`, of all of them.
  void resolveQueries(bool wait) const;
  void writePoint(std::uint32_t index, const glm::vec4* position, const glm::vec3* displacement);
  void endFrame() override;
  void snapshotHealth();  // after the frame's health pass: copy into the next ring slot, then a fence
  void forgetSnapshots();
  void growPairList(const gpu::PairState& state);

  // Declared first so it is destroyed last, after every GL object below.
  gl::HeadlessContext owned_context_;
  gl::ContextInfo context_info_;
  Scene scene_;
  GpuSolverOptions options_;
  Topology topo_;
  long long substeps_ = 0;
  bool pairs_checked_ = false;   // forcesIntegrate checked the current positions' travel
  bool health_checked_ = false;  // the health pass ran on the current state
  int held_ = -1;
  std::uint32_t max_groups_x_ = 65535;

  StateBuffers state_[2];
  int current_ = 0;
  gl::Buffer params_, offsets_, neighbors_, colliders_, health_;
  gl::Buffer point_mass_;  // PointMass per point, rewritten with the params
  SpringColouring colouring_;
  gl::Buffer coloured_springs_;                    // ColouredSpring, enabled springs in colour order
  gl::Buffer xpbd_lambda_;                         // float per coloured spring, XPBD with iterations > 1 only
  std::vector<std::uint32_t> colour_start_;        // colour c is coloured_springs_[colour_start_[c] .. [c+1])
  std::vector<std::uint32_t> point_colour_start_;  // VBD: colour c is coloured_points_[start[c] .. [c+1])
  gl::Buffer coloured_points_;                     // VBD: point indices grouped by colour (colourPoints)
  gl::Buffer vbd_inertia_;                         // VBD with iterations > 1: vec4 per point, the prediction y
  bool one_group_ = false;                         // the one-dispatch path runs this scene
  bool tiled_ = false;                             // the stretch limit runs tiled (GpuPath::Tiled)
  bool fused_frame_ = false;                       // fusedFrame()
  int terms_held_ = 0;                             // GpuSolverOptions::self_terms_held as chosen
  StretchTiling tiling_;                           // its blocks, when it does
  // Each grid direction's rest length, when all its enabled springs share one (0: disabled or none): then
  // the tiled kernel finds partners and rests from the grid instead of the ColourPartner table.
  std::vector<float> grid_rests_;
  gl::Buffer colour_partners_;  // ColourPartner table (Gauss-Seidel stretch, per point)
  gl::Buffer tethers_;          // Tether per point and slot, once the scene asks for them
  int tether_slots_ = 0;        // anchors per point; 0: none built, or a cloth without pins
  gl::Buffer grid_points_, grid_counts_, grid_start_, grid_blocks_, grid_scatter_, grid_sorted_;
  gl::Buffer pair_control_, pair_anchor_, pair_start_, pair_list_;
  std::uint64_t pair_capacity_ = 0;
  std::uint32_t pair_entries_ = 0;  // candidate entries of the last list build, as the last health read saw
  gl::Buffer normals_, tangents_, vertex_tri_offsets_, vertex_tris_, triangles_, uvs_, pick_;
  Programs programs_;
  std::vector<PlannedDispatch> plan_;
  // What stepFrame() dispatches off the one-dispatch path, worked out with plan_: `substep` steps_per_frame
  // times, then `tail` once, then the health check (endFrame()). passes(), framePasses(), the dispatch
  // counts and the traffic model read it. Mostly the substep is plan_ and the tail empty; on the fused
  // frame (fusedFrame()) the substep is the one fused dispatch and the tail the last substep's stretch limit.
  struct FramePlan {
    std::vector<PlannedDispatch> substep, tail;
  };
  FramePlan frame_;
  gl::Defines defines_;
  bool enabled_springs_[kSpringTypeCount] = {true, true, true};

  static constexpr int kHealthSlots = 2;  // the newest frame and the one before it
  struct HealthSlot {
    gl::Fence fence;  // empty: the slot holds nothing yet
    long long substeps = -1;
  };
  gl::Buffer health_ring_;  // kHealthSlots snapshots (gpu_solver_step.cpp), mapped for reading
  HealthSlot health_slots_[kHealthSlots];
  int newest_slot_ = -1;

  bool timer_queries_ = false;
  bool timing_break_ = true;  // the next timed dispatch starts a new run of timestamps
  mutable std::vector<PassTiming> timings_;
  mutable std::vector<PendingQuery> pending_;
  mutable std::vector<gl::Query> spare_queries_;
};

}  // namespace drape
