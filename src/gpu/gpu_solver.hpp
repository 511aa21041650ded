// GPU solver: the passes of docs/design.md section 2 as OpenGL 4.5 compute kernels over SSBOs
// (glsl/sim/*.comp), compiled per scene with #defines, fused where the data flow allows, and
// consistent with CpuSolver<float> (tests/gpu_*_gl_test.cpp). Needs a current GL 4.5 context.
//
// One substep is this list of dispatches (a pass with nothing to do is not dispatched):
//   forces+integrate[+collide | +grid_count]   per point: gather springs (+ wind), Verlet, then the
//                                               point's collisions, or its hash-grid count when a
//                                               self-collision pass comes next
//   grid_build                                  hash-grid counting sort (prefix sum, scatter, rank) in one
//                                               work group, up to 4096 buckets; beyond that 5 dispatches:
//                                               grid_scan grid_scan_blocks grid_scan_offsets grid_scatter grid_rank
//   self_collide[+collide]                      Jacobi self-collision, then the point's collisions
//   limit_stretch_colour                        Gauss-Seidel stretch scheme: one dispatch per spring colour
//                                               and stretch pass, each moving both ends of its springs in place
//   limit_stretch                               Jacobi stretch scheme: once per stretch pass
// Every pass that reads other points' positions reads one copy of the state and writes the other
// (Jacobi / ping-pong), so no invocation sees a neighbour's half-finished update.
#pragma once

#include "core/colouring.hpp"
#include "core/solver.hpp"
#include "gl/context.hpp"
#include "gl/objects.hpp"
#include "gl/shader_source.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace drape {

struct GpuSolverOptions {
  std::uint32_t buckets = 0;         // self-collision hash buckets, a power of two; 0: one per point, as the CPU grid
  bool timing = false;               // time every pass (GL timer queries; else glFinish + wall clock, which stalls)
  double sane_bound = 1e5;           // m; a point beyond this on any axis is reported by readHealth()
  std::size_t max_buffer_bytes = 0;  // largest buffer allowed; 0: GL_MAX_SHADER_STORAGE_BLOCK_SIZE
};

// The scene needs more than the GPU allows (buffer size, work groups, memory). Thrown before any
// dispatch, with the sizes involved.
class GpuLimitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the blow-up check in the integrate kernel saw since the last clearHealth().
struct GpuHealth {
  bool non_finite = false;     // a position or displacement became NaN or infinite
  bool out_of_bounds = false;  // a point went beyond GpuSolverOptions::sane_bound
  long long first_point = -1;  // smallest index that raised a flag, -1 if none
  bool ok() const { return !non_finite && !out_of_bounds; }
};

// The hash grid as the GPU built it, read back for tests.
struct GpuGrid {
  std::vector<glm::ivec3> cells;       // per point
  std::vector<std::uint32_t> buckets;  // per point: hashCell(cell) & (bucket count - 1)
  std::vector<std::uint32_t> arrival;  // per point: its slot in the bucket's atomic (thread-timing) order
  std::vector<std::uint32_t> start;    // bucket count + 1 prefix sums
  std::vector<std::uint32_t> sorted;   // point indices grouped by bucket, ascending within one
};

class GpuSolver final : public Solver {
 public:
  // Uses the current context. `context`, when not empty, is owned by the solver and outlives its GL
  // objects (makeSolver uses this for `--solver gpu`). Throws GpuLimitError before allocating anything
  // when the scene does not fit, gl::ShaderError when a kernel does not compile.
  explicit GpuSolver(Scene scene, GpuSolverOptions options = {}, gl::HeadlessContext context = {});
  ~GpuSolver() override;
  GpuSolver(const GpuSolver&) = delete;
  GpuSolver& operator=(const GpuSolver&) = delete;

  std::string name() const override { return "gpu"; }
  const Scene& scene() const override { return scene_; }
  const Topology& topology() const override { return topo_; }

  void step() override;
  void reset() override;
  void setParams(const ClothSpec& cloth, const SimParams& sim) override;
  std::vector<glm::dvec3> readPositions() override;
  std::vector<glm::dvec3> readDisplacements() override;
  long long substeps() const override { return substeps_; }
  std::vector<std::string> passes() const override;
  int dispatchesPerFrame() const override;
  std::vector<PassTiming> timings() const override;
  void resetTimings() override;

  // The stages of step(), public so tests can run each on a chosen state and compare it with the CPU
  // passes it fuses.
  void forcesIntegrate();  // CpuSolver accumulateForces + integrate (+ collide when there is no self-collision)
  void selfCollide();      // CpuSolver selfCollide (+ collide): hash grid, then the Jacobi correction
  void limitStretch();     // CpuSolver limitStretch: sim.stretch_passes dispatches
  bool collideFusedWithIntegrate() const { return !scene_.sim.self_collision; }
  // Replaces the state (positions, displacements) and the substep count (wind depends on time), as
  // CpuSolver::setState; pin flags stay.
  void uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, long long substeps);
  GpuGrid readGrid();  // after selfCollide(): the grid it used

  // For the renderer. The state lives in two buffers that passes alternate between, so ask for the
  // current one every frame. vec4 per point (std430): xyz position, w = 1.
  const gl::Buffer& positionBuffer() const { return state_[current_].position; }
  const gl::Buffer& normalBuffer() const { return normals_; }    // vec4: unit normal, w = 0
  const gl::Buffer& tangentBuffer() const { return tangents_; }  // vec4: unit tangent (+u), w = bitangent sign
  void computeNormals();  // once per frame before drawing: area-weighted normals, tangents from UVs

  // Mouse dragging. setPosition moves a point and keeps its displacement (x_prev moves with it, so no
  // velocity kick); a held point behaves as pinned at the target until releasePoint().
  void setPosition(std::uint32_t index, glm::vec3 position);
  void holdPoint(int index, glm::vec3 target);
  void releasePoint();
  // On the GPU: the point within `radius` of the ray nearest to its origin (smallest t >= 0, ties to the
  // smallest index), -1 if none. One explicit read-back of a few bytes.
  int pickPoint(glm::vec3 origin, glm::vec3 direction, float radius);

  GpuHealth readHealth();  // explicit read-back; cheap, but it waits for the GPU
  void clearHealth();

  std::size_t gpuMemoryBytes() const;  // all buffers this solver allocated
  // The #defines the scene's kernels were compiled with (NUM_SPHERES, NUM_PLANES, SELF_COLLISION, WIND).
  const gl::Defines& defines() const { return defines_; }
  const gl::ContextInfo& contextInfo() const { return context_info_; }

 private:
  enum PassId {
    kForcesIntegrate,
    kGridCount,
    kGridBuild,
    kGridScan,
    kGridScanBlocks,
    kGridScanOffsets,
    kGridScatter,
    kGridRank,
    kSelfCollide,
    kLimitStretch,
    kLimitStretchColoured,
    kNormals,
    kPick,
    kPassCount
  };
  struct StateBuffers {
    gl::Buffer position;      // vec4 per point
    gl::Buffer displacement;  // vec4 per point, w = pin flag
  };
  struct Programs {
    gl::Program forces_integrate, grid_count, grid_build, grid_scan[3], grid_scatter, grid_rank, self_collide;
    gl::Program limit_stretch, limit_stretch_coloured;
    gl::Program normals, pick[2];  // compiled on first use
  };
  struct PendingQuery {
    PassId pass;
    gl::Query query;
  };

  void checkLimits() const;
  void allocate();
  void allocateGrid();
  void uploadParams();
  void uploadAdjacency();
  gl::Defines sceneDefines() const;
  void compilePrograms();
  std::string passName(PassId pass) const;
  std::uint32_t bucketCount() const;
  std::uint32_t scanBlocks() const;
  bool gridInOneGroup() const;

  void bindShared() const;
  void bindState(int in, int out) const;
  glm::uvec3 groupsFor(std::uint64_t invocations, std::uint32_t local_size) const;
  // Runs one dispatch (timed when timing is on) followed by the storage barrier the next pass needs.
  void dispatch(PassId pass, const gl::Program& program, glm::uvec3 groups);
  void dispatchPingPong(PassId pass, const gl::Program& program);
  void resolveQueries() const;
  void writePoint(std::uint32_t index, const glm::vec4* position, const glm::vec4* displacement);
  void discardGridCount();

  // Declared first so it is destroyed last, after every GL object below.
  gl::HeadlessContext owned_context_;
  gl::ContextInfo context_info_;
  Scene scene_;
  GpuSolverOptions options_;
  Topology topo_;
  long long substeps_ = 0;
  bool grid_counted_ = false;  // forcesIntegrate counted the current positions into the grid
  int held_ = -1;
  std::uint32_t max_groups_x_ = 65535;

  StateBuffers state_[2];
  int current_ = 0;
  gl::Buffer params_, offsets_, neighbors_, colliders_, health_;
  gl::Buffer point_mass_;  // PointMass per point, rewritten with the params
  SpringColouring colouring_;
  gl::Buffer coloured_springs_;              // ColouredSpring, enabled springs in colour order
  std::vector<std::uint32_t> colour_start_;  // colour c is coloured_springs_[colour_start_[c] .. [c+1])
  gl::Buffer grid_points_, grid_counts_, grid_start_, grid_blocks_, grid_scatter_, grid_sorted_;
  gl::Buffer normals_, tangents_, vertex_tri_offsets_, vertex_tris_, triangles_, uvs_, pick_;
  Programs programs_;
  gl::Defines defines_;
  bool enabled_springs_[kSpringTypeCount] = {true, true, true};

  bool timer_queries_ = false;
  mutable std::vector<PassTiming> timings_;
  mutable std::vector<PendingQuery> pending_;
  mutable std::vector<gl::Query> spare_queries_;
};

}  // namespace drape
