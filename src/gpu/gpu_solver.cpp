#include "gpu/gpu_solver.hpp"

#include "gpu/device_limits.hpp"
#include "gpu/kernels.hpp"
#include "gpu/traffic.hpp"

#include <bit>
#include <stdexcept>

static_assert(drape::gpu::kHealthNonFinite == drape::Health::kNonFinite &&
              drape::gpu::kHealthOutOfBounds == drape::Health::kOutOfBounds &&
              drape::gpu::kHealthOverstretched == drape::Health::kOverstretched);

namespace drape {

GpuSolver::GpuSolver(Scene scene, GpuSolverOptions options, gl::HeadlessContext context)
    : owned_context_(std::move(context)), scene_(std::move(scene)), options_(options) {
  if (owned_context_) owned_context_.makeCurrent();
  // Without a current context the GL entry points are null or answer nothing: say so, do not crash.
  if (glGetString == nullptr || glGetString(GL_VERSION) == nullptr)
    throw std::logic_error("GpuSolver: no current OpenGL 4.5 context (make one, e.g. gl::HeadlessContext::create())");
  context_info_ = gl::queryContextInfo();
  if (options_.self_terms_held < -1 || options_.self_terms_held > 32)
    throw std::invalid_argument("gpu solver: self_terms_held must be -1 (per device) or 0 to 32, not " +
                                std::to_string(options_.self_terms_held));
  terms_held_ = options_.self_terms_held >= 0 ? options_.self_terms_held : context_info_.software ? 0 : 8;
  if (options_.buckets != 0 && !std::has_single_bit(options_.buckets))
    throw std::invalid_argument("gpu solver: buckets must be a power of two, not " + std::to_string(options_.buckets));
  device_ = gpu::queryDeviceLimits(options_.max_buffer_bytes, context_info_.software);
  const gpu::SceneNeeds needs = gpu::sceneNeeds(scene_);
  const gpu::ListLayout lists = gpu::listLayout(std::uint64_t(scene_.cloth.pointCount()), options_.buckets);
  gpu::checkLimits(scene_, needs, lists.buckets, device_);
  topo_ = buildTopology(scene_.cloth);
  colouring_ = colourSprings(topo_);
  try {
    cloth_ = std::make_unique<gpu::DeviceCloth>(scene_, topo_);
    cloth_->uploadParams(scene_, {options_.pair_margin, options_.health, lists.buckets});
    cloth_->uploadSprings(colouring_, needs);
    ring_.allocate();
    replan(true);
  } catch (const gl::GlError& e) {
    throw GpuLimitError("gpu solver: allocating the buffers for a " + std::to_string(topo_.pointCount()) +
                        "-point cloth failed: " + e.what());
  }
  if (glGetError() == GL_OUT_OF_MEMORY)
    throw GpuLimitError("gpu solver: out of GPU memory allocating the buffers for a " +
                        std::to_string(topo_.pointCount()) + "-point cloth");
  timer_.configure(options_.timing, options_.timing && gl::timerQueriesWork());
  reset();
}

GpuSolver::~GpuSolver() {
  // The members' GL objects are deleted after this body, in the owned context if there is one.
  if (owned_context_) owned_context_.makeCurrent();
}

std::string GpuSolver::name() const {
  switch (options_.path) {
    case GpuPath::General:
      return "gpu-general";
    case GpuPath::Tiled:
      return "gpu-tiled";
    case GpuPath::OneDispatch:
      return "gpu-onedispatch";
    case GpuPath::Auto:
      break;
  }
  return "gpu";
}

// What the plan's passes read is allocated the first time a scene asks for it; the plan is then worked out, a
// forced path that does not fit refused (at construction; a live change falls back to the general path), and
// its kernels compiled.
void GpuSolver::replan(bool constructing) {
  const gpu::SceneNeeds needs = gpu::sceneNeeds(scene_);
  cloth_->prepareFor(needs, scene_.cloth.thickness);
  const std::uint64_t n = std::uint64_t(topo_.pointCount());
  if (needs.contacts && !lists_.allocated())
    lists_.allocate(scene_.cloth, options_.pair_margin, n, gpu::listLayout(n, options_.buckets), options_.pair_capacity,
                    device_.max_buffer_bytes, gpu::groupsFor(n, device_.max_groups_x));
  plan_ = gpu::makePlan(
      {scene_, topo_, colouring_, cloth_->counts(), options_.path, device_, options_.buckets, terms_held_});
  if (constructing && !plan_.path.refusal.empty()) throw GpuLimitError(plan_.path.refusal);
  cloth_->setColourPartners(plan_.path.colour_partners, colouring_, needs);
  if (!runner_) runner_ = std::make_unique<gpu::PlanRunner>(*cloth_, lists_, programs_, timer_, device_.max_groups_x);
  programs_.prepare(plan_);
}

void GpuSolver::setParams(const ClothSpec& cloth, const SimParams& sim) {
  const gpu::SceneNeeds before = plan_.needs;
  const double thickness = scene_.cloth.thickness;
  applyLiveParams(scene_, cloth, sim);
  if (scene_.cloth.thickness != thickness && !scene_.meshes.empty()) cloth_->uploadColliders(scene_);
  const gpu::SceneNeeds needs = gpu::sceneNeeds(scene_);
  gpu::checkLimits(scene_, needs, plan_.lists.buckets, device_);
  if (needs.springs != before.springs) cloth_->uploadSprings(colouring_, needs);
  cloth_->uploadParams(scene_, {options_.pair_margin, options_.health, plan_.lists.buckets});
  lists_.invalidate();  // thickness may have changed, and with it the lists' reach
  replan(false);        // self-collision, the spring types, the stretch passes may have changed what runs
  health_checked_ = false;
}

void GpuSolver::step() {
  timer_.pause();
  runner_->bindShared();
  runner_->run(plan_, plan_.substep, substeps_);
  health_checked_ = false;
}

void GpuSolver::stepFrame() {
  timer_.pause();
  runner_->bindShared();
  for (int repeat = 0; repeat < plan_.frame.repeats; ++repeat)
    runner_->run(plan_, plan_.frame.substep, substeps_, repeat);
  runner_->run(plan_, plan_.frame.tail, substeps_);
  health_checked_ = runner_->checkedHealth();
  endFrame();
}

// After the frame's health check, so that a state made bad by any pass is reported in the frame that made it.
void GpuSolver::endFrame() {
  ring_.snapshot(cloth_->health(), lists_.control(), substeps_);
}

void GpuSolver::runStage(gpu::Stage stage) {
  runner_->bindShared();
  runner_->run(plan_, gpu::stageDispatches(plan_, stage, runner_->travelChecked()), substeps_);
}

void GpuSolver::reset() {
  cloth_->reset();
  substeps_ = 0;
  runner_->forgetTravel();
  clearHealth();
}

void GpuSolver::uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, long long substeps) {
  cloth_->uploadState(x, v);
  substeps_ = substeps;
  runner_->forgetTravel();
  health_checked_ = false;
}

void GpuSolver::setPosition(std::uint32_t index, glm::vec3 position) {
  cloth_->setPosition(index, position);
  health_checked_ = false;
}

void GpuSolver::holdPoint(int index, glm::vec3 target) {
  cloth_->holdPoint(index, target);
  health_checked_ = false;
}

void GpuSolver::releasePoint() {
  cloth_->releasePoint();
  health_checked_ = false;
}

GpuGrid GpuSolver::readGrid() const {
  return lists_.readGrid(std::uint64_t(topo_.pointCount()), plan_.lists.buckets);
}

GpuPairs GpuSolver::readPairs() const {
  return lists_.readPairs(std::uint64_t(topo_.pointCount()));
}

std::string GpuSolver::tiledStretchMisfit() const {
  return gpu::tiledMisfit(plan_.needs, stretchTiling(), device_);
}

GpuSolver::StretchTiling GpuSolver::stretchTiling() const {
  return gpu::stretchTiling(plan_.needs, topo_, colouring_, device_);
}

std::vector<PassTiming> GpuSolver::timings() const {
  return timer_.timings([this](gpu::Pass pass) { return gpu::passLabel(plan_, pass); });
}

void GpuSolver::checkHealth() {
  runStage(gpu::Stage::Health);
  health_checked_ = true;
}

// A list overflow the read finds grows the list buffer (PairLists::grow).
void GpuSolver::readListState(const gpu::PairState& state) {
  pair_entries_ = state.total;
  lists_.grow(state, device_.max_buffer_bytes);
}

Health GpuSolver::healthOf(const gpu::Health& flags, long long substeps) const {
  Health out;
  out.flags = flags.flags;
  out.first_point = flags.flags != 0 ? (long long)flags.first_point : -1;
  out.substeps = substeps;
  return out;
}

Health GpuSolver::health() {
  if (!health_checked_) checkHealth();
  if (lists_.allocated()) readListState(lists_.readState());
  return healthOf(cloth_->readHealth(), substeps_);
}

Health GpuSolver::recentHealth() {
  const std::optional<gpu::HealthRing::Recent> recent = ring_.recent();
  if (!recent) return health();  // no frame ended since the reset: nothing in flight to spare
  if (lists_.allocated()) readListState(recent->snapshot.pairs);
  return healthOf(recent->snapshot.health, recent->substeps);
}

void GpuSolver::clearHealth() {
  cloth_->clearHealth();
  health_checked_ = false;  // the next health() checks the current state again
  ring_.forget();           // their flags were raised before this
}

double GpuSolver::bytesPerPointPerSubstep() const {
  const double n = double(topo_.pointCount());
  return gpu::bytesPerPointPerSubstep(plan_,
                                      {n, double(cloth_->counts().adjacency_entries) / n, double(pair_entries_) / n});
}

long long GpuSolver::deviceMemoryBytes() const {
  return (long long)(cloth_->bytes() + lists_.bytes() + ring_.bytes());
}

}  // namespace drape
