// GPU solver: the passes of docs/design.md section 2 as OpenGL 4.5 compute kernels over SSBOs, bit for bit
// CpuSolver<float> on llvmpipe (tests/gpu_*_gl_test.cpp). Needs a current GL 4.5 context.
//
// A facade over the rooms of src/gpu (docs/design.md section 4): the plan (plan.hpp: what a substep and a frame
// dispatch, worked out without GL from the scene, the path and the device's limits), the kernel table
// (kernels.hpp), the device cloth (device_cloth.hpp: every buffer), the self-collision lists (pair_lists.hpp),
// the health ring (health_ring.hpp), the pass timer (pass_timer.hpp), and the runner that dispatches a plan
// (plan_runner.hpp). The kernels are GLSL schedules of phases written once (glsl/sim/phases).
#pragma once

#include "core/colouring.hpp"
#include "core/solver.hpp"
#include "gl/context.hpp"
#include "gpu/device_cloth.hpp"
#include "gpu/gpu_options.hpp"
#include "gpu/health_ring.hpp"
#include "gpu/pair_lists.hpp"
#include "gpu/pass_timer.hpp"
#include "gpu/plan.hpp"
#include "gpu/plan_runner.hpp"
#include "gpu/programs.hpp"

#include <memory>
#include <string>
#include <vector>

namespace drape {

class GpuSolver final : public Solver {
 public:
  using StretchTiling = gpu::StretchTiling;

  // Uses the current context. `context`, when not empty, is owned by the solver and outlives its GL objects.
  // Throws GpuLimitError before allocating anything when the scene does not fit (or a forced path does not),
  // gl::ShaderError when a kernel does not compile.
  explicit GpuSolver(Scene scene, GpuSolverOptions options = {}, gl::HeadlessContext context = {});
  ~GpuSolver() override;
  GpuSolver(const GpuSolver&) = delete;
  GpuSolver& operator=(const GpuSolver&) = delete;

  // "gpu", or the forced path's name ("gpu-general", "gpu-tiled", "gpu-onedispatch"), as the factory calls them.
  std::string name() const override;
  const Scene& scene() const override { return scene_; }
  const Topology& topology() const override { return topo_; }

  void step() override;
  void stepFrame() override;  // the frame plan: one dispatch on the one-dispatch path
  void reset() override;
  void setParams(const ClothSpec& cloth, const SimParams& sim) override;
  std::vector<glm::dvec3> readPositions() override { return cloth_->readPositions(); }
  std::vector<glm::dvec3> readDisplacements() override { return cloth_->readDisplacements(); }
  long long substeps() const override { return substeps_; }
  std::vector<std::string> passes() const override { return gpu::substepListing(plan_); }
  std::vector<std::string> framePasses() const override { return gpu::frameListing(plan_); }
  int dispatchesPerFrame() const override { return gpu::dispatchesPerFrame(plan_); }
  double dispatchesPerSubstep() const override { return gpu::dispatchesPerSubstep(plan_); }
  std::vector<PassTiming> timings() const override;
  void resetTimings() override { timer_.reset(); }

  // The plan this solver runs, and the path it chose: whether the one-dispatch path or the tiled stretch
  // limit runs the scene, and, where one cannot, why not ("" if it can).
  const gpu::Plan& plan() const { return plan_; }
  bool oneDispatch() const { return plan_.path.path == GpuPath::OneDispatch; }
  std::string oneDispatchMisfit() const { return plan_.path.one_dispatch_misfit; }
  bool tiledStretch() const { return plan_.path.path == GpuPath::Tiled; }
  bool tiledFromGrid() const { return tiledStretch() && !plan_.path.grid_rests.empty(); }  // springs from the grid
  std::string tiledStretchMisfit() const;
  StretchTiling stretchTiling() const;  // the blocks this scene's colouring allows on this device
  bool fusedFrame() const { return plan_.path.fused_frame; }

  // The stages of step(), public so tests can run each on a chosen state and compare it with the CPU passes it
  // fuses: forces + integrate (+ collide), self-collision (+ collide; the lists' travel check first where no
  // integrate checked it), the stretch passes, XPBD's and VBD's sweeps, the collide pass, the tethers.
  void forcesIntegrate() { runStage(gpu::Stage::Integrate); }
  void selfCollide() { runStage(gpu::Stage::SelfCollide); }
  void limitStretch() { runStage(gpu::Stage::Stretch); }
  void solveXpbd() { runStage(gpu::Stage::Xpbd); }
  void solveVbd() { runStage(gpu::Stage::Vbd); }
  void collide() { runStage(gpu::Stage::Collide); }
  void tether() { runStage(gpu::Stage::Tether); }
  void collideFaces() { runStage(gpu::Stage::Faces); }       // the face contacts (+ the collisions again)
  void collideLast() { runStage(gpu::Stage::CollideLast); }  // the collisions again, where no face contacts run
  bool usesTethers() const { return plan_.tether_slots > 0; }
  bool collideFusedWithIntegrate() const { return plan_.needs.fusion.collide_in_integrate; }
  // Replaces the state (positions, displacements) and the substep count (wind depends on time), as
  // CpuSolver::setState; pin flags stay.
  void uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, long long substeps);
  GpuGrid readGrid() const;    // after selfCollide(): the grid of the last list build
  GpuPairs readPairs() const;  // after selfCollide(): the lists it used

  // For the renderer. The state lives in two buffers that passes alternate between, so ask for the current one
  // every frame. vec4 per point (std430): xyz position, w the pin flag (1 pinned or held).
  const gl::Buffer& positionBuffer() const { return cloth_->position(); }
  const gl::Buffer& healthBuffer() const { return cloth_->health(); }  // gpu::Health: the flags the check raised

  // Mouse dragging. setPosition moves a point and keeps its displacement (x_prev moves with it, so no velocity
  // kick); a held point behaves as pinned at the target until releasePoint().
  void setPosition(std::uint32_t index, glm::vec3 position);
  void holdPoint(int index, glm::vec3 target);
  void releasePoint();
  // On the GPU: the point within `radius` of the ray nearest to its origin (smallest t >= 0, ties to the
  // smallest index), -1 if none. One explicit read-back of a few bytes.
  int pickPoint(glm::vec3 origin, glm::vec3 direction, float radius) {
    return runner_->pickPoint(plan_, origin, direction, radius);
  }

  // The flags raised since the last clearHealth() (reset() clears them). A state that was stepped or replaced
  // since the last check (step() without stepFrame(), uploadState()) is checked first, so the answer is always
  // about the current state. One read-back of a few bytes: it waits for the GPU.
  Health health() override;
  // No wait in the steady state: the newest frame's flags the GPU has copied into the health ring (and the list
  // build's overflow, which grows the list buffer as health() does); waits only for the frame before the newest
  // if even that one is still running.
  Health recentHealth() override;
  void clearHealth();
  void checkHealth();  // the health pass on the current state, as a frame runs it after its last substep
  void finish() override { gl::finish(); }
  bool timesPasses() const { return timer_.timing(); }
  // The traffic model (traffic.hpp) of the frame plan, with the candidates the last health read saw.
  double bytesPerPointPerSubstep() const override;
  long long deviceMemoryBytes() const override;  // all buffers this solver allocated
  // The scene's #defines every kernel shares (NUM_SPHERES, NUM_PLANES, SELF_COLLISION, WIND, UNIFORM_MASS, ...),
  // and everything one pass's kernel is compiled with.
  gl::Defines defines() const { return gpu::sceneDefines(plan_.needs); }
  gl::Defines kernelDefines(gpu::Pass pass) const { return gpu::kernelDefines(plan_, pass); }
  const gl::ContextInfo& contextInfo() const { return context_info_; }

 private:
  void endFrame() override;  // the frame's health flags into the ring
  void runStage(gpu::Stage stage);
  void replan(bool constructing);  // the plan for the current scene, its kernels and the buffers it reads
  void readListState(const gpu::PairState& state);
  Health healthOf(const gpu::Health& flags, long long substeps) const;

  // Declared first so it is destroyed last, after every GL object below.
  gl::HeadlessContext owned_context_;
  gl::ContextInfo context_info_;
  Scene scene_;
  GpuSolverOptions options_;
  gpu::DeviceLimits device_;
  Topology topo_;
  SpringColouring colouring_;
  int terms_held_ = 0;  // GpuSolverOptions::self_terms_held as chosen for the device
  std::unique_ptr<gpu::DeviceCloth> cloth_;
  gpu::PairLists lists_;
  gpu::Programs programs_;
  gpu::PassTimer timer_;
  gpu::HealthRing ring_;
  std::unique_ptr<gpu::PlanRunner> runner_;
  gpu::Plan plan_;
  long long substeps_ = 0;
  bool health_checked_ = false;     // the health pass ran on the current state
  std::uint32_t pair_entries_ = 0;  // candidate entries of the last list build, as the last health read saw
};

}  // namespace drape
