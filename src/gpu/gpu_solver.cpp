#include "gpu/gpu_solver.hpp"

#include "core/cloth_mesh.hpp"
#include "core/derived.hpp"
#include "core/tethers.hpp"
#include "gl/shader.hpp"
#include "gpu/layout.hpp"
#include "gpu/mesh_colliders.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdio>
#include <string>

namespace drape {

namespace {

constexpr GLbitfield kUpdatable = GL_DYNAMIC_STORAGE_BIT;

std::string mebibytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  return text;
}

std::uint64_t springCount(const ClothSpec& c, SpringType type) {
  if (c.mesh)
    return std::uint64_t(std::count_if(c.mesh->springs.begin(), c.mesh->springs.end(),
                                       [type](const MeshSpring& s) { return s.type == type; }));
  const std::uint64_t W = std::uint64_t(c.num_width_points), H = std::uint64_t(c.num_height_points);
  switch (type) {
    case SpringType::Structural:
      return 2 * W * H - W - H;
    case SpringType::Shearing:
      return 2 * (W - 1) * (H - 1);
    case SpringType::Bending:
      return 2 * W * H - 2 * W - 2 * H;
  }
  return 0;
}

}  // namespace

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
  for (int t = 0; t < kSpringTypeCount; ++t)
    enabled_springs_[t] = scene_.cloth.springEnabled(SpringType(t));
  GLint groups = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
  max_groups_x_ = std::uint32_t(groups);
  // Before the topology: a cloth too large for this GPU must fail fast, without building gigabytes of
  // springs on the CPU first.
  checkLimits();
  topo_ = buildTopology(scene_.cloth);
  colouring_ = colourSprings(topo_);
  try {
    allocate();
  } catch (const gl::GlError& e) {
    throw GpuLimitError("gpu solver: allocating the buffers for a " + std::to_string(topo_.pointCount()) +
                        "-point cloth failed: " + e.what());
  }
  if (glGetError() == GL_OUT_OF_MEMORY)
    throw GpuLimitError("gpu solver: out of GPU memory allocating the buffers for a " +
                        std::to_string(topo_.pointCount()) + "-point cloth");
  timer_queries_ = options_.timing && gl::timerQueriesWork();
  resetTimings();
  allocateLambda();
  allocateVbd();
  allocateTethers();
  compilePrograms();
  choosePath(true);
  buildPlan();
  reset();
}

// XPBD's multipliers need memory only when a substep sweeps more than once (the first sweep of a
// substep starts them at 0 and does not read them).
void GpuSolver::allocateLambda() {
  if (scene_.sim.integrator != Integrator::Xpbd || scene_.sim.iterations <= 1) return;
  const std::size_t bytes = std::max<std::size_t>(colour_start_.back(), 1) * sizeof(float);
  if (xpbd_lambda_.id() == 0 || xpbd_lambda_.size() < bytes) xpbd_lambda_ = gl::Buffer::create(bytes, nullptr, 0);
}

void GpuSolver::allocateVbd() {
  if (scene_.sim.integrator != Integrator::Vbd) return;
  if (coloured_points_.id() == 0) {
    const PointColouring colouring = colourPoints(topo_);
    point_colour_start_ = colouring.start;
    coloured_points_ = gl::Buffer::fromVector(colouring.points, 0);
  }
  if (scene_.sim.iterations > 1 && vbd_inertia_.id() == 0)
    vbd_inertia_ = gl::Buffer::create(std::size_t(topo_.pointCount()) * sizeof(glm::vec4), nullptr, 0);
}

void GpuSolver::allocateTethers() {
  if (!scene_.sim.tethers || tethers_.id() != 0) return;
  static_assert(gpu::kNoTether == kNoAnchor);
  const Tethers t = buildTethers(topo_);
  tether_slots_ = t.slots;
  if (t.slots == 0) return;
  std::vector<gpu::Tether> entries(t.anchor.size());
  for (std::size_t k = 0; k < entries.size(); ++k)
    entries[k] = {t.anchor[k], float(t.rest[k])};
  tethers_ = gl::Buffer::fromVector(entries, 0);
  // Its code depends on nothing in the scene but the slots.
  programs_.tether = gl::compileCompute("sim/tether.comp", {{"TETHER_SLOTS", std::to_string(t.slots)}});
}

GpuSolver::~GpuSolver() {
  // The members' GL objects are deleted after this body, in the owned context if there is one.
  if (owned_context_) owned_context_.makeCurrent();
}

void GpuSolver::checkLimits() const {
  const ClothSpec& c = scene_.cloth;
  const std::uint64_t n = std::uint64_t(c.pointCount());
  std::uint64_t springs = 0;
  for (int t = 0; t < kSpringTypeCount; ++t)
    if (enabled_springs_[t]) springs += springCount(c, SpringType(t));
  const std::uint64_t buckets = options_.buckets ? options_.buckets : derived::hashBucketCount(n);
  const std::uint64_t limit = maxBufferBytes();
  const std::string cloth =
      c.mesh ? std::to_string(n) + "-point mesh cloth"
             : std::to_string(c.num_width_points) + "x" + std::to_string(c.num_height_points) + " cloth";
  struct Need {
    const char* what;
    std::uint64_t bytes;
  };
  const Need needs[] = {
      {"positions", n * sizeof(glm::vec4)},
      {"point masses", n * sizeof(gpu::PointMass)},
      {"spring adjacency", 2 * springs * sizeof(gpu::Neighbor)},
      {"coloured springs", springs * sizeof(gpu::ColouredSpring)},
      {"hash-grid points", scene_.sim.self_collision ? n * sizeof(gpu::GridPoint) : 0},
      {"hash-grid buckets", scene_.sim.self_collision ? (buckets + 1) * sizeof(std::uint32_t) : 0},
      {"self-collision anchors", scene_.sim.self_collision ? n * sizeof(glm::vec4) : 0},
      {"colliders and mesh distance fields", colliderCount(scene_) * sizeof(gpu::Collider)},
  };
  for (const Need& need : needs)
    if (need.bytes > limit)
      throw GpuLimitError("gpu solver: a " + cloth + " needs " + mebibytes(need.bytes) + " for its " + need.what +
                          ", more than the " + mebibytes(limit) + " one shader storage buffer may hold here" +
                          (options_.max_buffer_bytes ? " (GpuSolverOptions::max_buffer_bytes)"
                                                     : " (GL_MAX_SHADER_STORAGE_BLOCK_SIZE)"));
  static_assert(kMaxClothPoints <= gpu::kNeighborIndexMask + 1LL, "point indices must fit Neighbor::index_type");
  GLint bindings = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  if (bindings < GLint(gpu::kBindingCount))
    throw GpuLimitError("gpu solver: needs " + std::to_string(gpu::kBindingCount) +
                        " shader storage binding points, this GPU has " + std::to_string(bindings) +
                        " (GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS)");
  GLint max_y = 0;
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 1, &max_y);
  const std::uint64_t groups = (n + gpu::kLocalSize - 1) / gpu::kLocalSize;
  if (groups > std::uint64_t(max_groups_x_) * std::uint64_t(max_y))
    throw GpuLimitError("gpu solver: a " + cloth + " needs " + std::to_string(groups) +
                        " work groups, more than GL_MAX_COMPUTE_WORK_GROUP_COUNT allows");
  if ((buckets + gpu::kScanBlock - 1) / gpu::kScanBlock > max_groups_x_)
    throw GpuLimitError("gpu solver: " + std::to_string(buckets) + " hash-grid buckets need more scan work groups " +
                        "than GL_MAX_COMPUTE_WORK_GROUP_COUNT allows");
}

std::uint64_t GpuSolver::maxBufferBytes() const {
  if (options_.max_buffer_bytes) return options_.max_buffer_bytes;
  GLint64 block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  return std::uint64_t(block);
}

std::uint32_t GpuSolver::bucketCount() const {
  return options_.buckets ? options_.buckets
                          : std::uint32_t(derived::hashBucketCount(std::uint64_t(topo_.pointCount())));
}

std::uint32_t GpuSolver::scanBlocks() const {
  return (bucketCount() + gpu::kScanBlock - 1) / gpu::kScanBlock;
}

std::uint32_t GpuSolver::pointScanBlocks() const {
  return std::uint32_t((std::uint64_t(topo_.pointCount()) + gpu::kScanBlock - 1) / gpu::kScanBlock);
}

bool GpuSolver::gridInOneGroup() const {
  return scanBlocks() == 1;
}

// List entries to allocate before any build has counted them: the points within reach in a flat sheet
// of the cloth's spacing (pi r^2 / spacing^2), four times over for folds, at least 32 per point, and no
// more than one buffer may hold. A build that needs more still gives the right answer (self_collide
// serves the points that did not fit from the grid), and the next health() grows the buffer.
std::uint64_t GpuSolver::pairCapacityEstimate() const {
  const ClothSpec& c = scene_.cloth;
  const std::uint64_t n = std::uint64_t(topo_.pointCount());
  const double spacing = std::max(
      1e-9, std::min(c.width / std::max(1, c.num_width_points - 1), c.height / std::max(1, c.num_height_points - 1)));
  const double reach = 2.0 * c.thickness * (1.0 + options_.pair_margin);
  const double per_point = std::min(1e6, 4.0 * 3.14159265358979 * (reach / spacing) * (reach / spacing));
  const std::uint64_t limit = maxBufferBytes();
  const std::uint64_t wanted = n * std::max<std::uint64_t>(32, std::uint64_t(per_point));
  return std::max<std::uint64_t>(1, std::min({wanted, limit / sizeof(std::uint32_t), std::uint64_t(0xffffffffu)}));
}

void GpuSolver::allocate() {
  const std::size_t n = std::size_t(topo_.pointCount());
  for (StateBuffers& s : state_) {
    s.position = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, kUpdatable);
    s.displacement = gl::Buffer::create(n * sizeof(glm::vec3), nullptr, kUpdatable);
  }
  params_ = gl::Buffer::create(sizeof(gpu::SimParams), nullptr, kUpdatable);
  point_mass_ = gl::Buffer::create(n * sizeof(gpu::PointMass), nullptr, kUpdatable);
  uploadParams();
  uploadAdjacency();

  std::vector<gpu::Collider> colliders;
  for (const SphereSpec& s : scene_.spheres)
    colliders.push_back({glm::vec4(glm::vec3(s.origin), float(s.radius)), glm::vec4(float(s.friction), 0, 0, 0)});
  for (const PlaneSpec& p : scene_.planes)
    colliders.push_back({glm::vec4(glm::vec3(p.point), float(p.friction)), glm::vec4(glm::vec3(p.normal), 0)});
  appendMeshColliders(colliders, scene_.meshes);
  colliders_ = gl::Buffer::fromVector(colliders, 0);
  health_ = gl::Buffer::create(sizeof(gpu::Health), nullptr, kUpdatable);
  health_ring_ = gl::Buffer::createReadMapped(kHealthSlots * (sizeof(gpu::Health) + sizeof(gpu::PairState)));
  pick_ = gl::Buffer::create(sizeof(gpu::PickResult), nullptr, kUpdatable);

  // Render data: the triangles around each vertex as CSR lists, in ascending triangle order.
  normals_ = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, 0);
  tangents_ = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, 0);
  normals_.clear();
  tangents_.clear();
  std::vector<std::uint32_t> tri_offsets(n + 1, 0);
  for (std::uint32_t v : topo_.triangles)
    ++tri_offsets[v + 1];
  for (std::size_t i = 0; i < n; ++i)
    tri_offsets[i + 1] += tri_offsets[i];
  std::vector<std::uint32_t> vertex_tris(topo_.triangles.size());
  std::vector<std::uint32_t> fill(tri_offsets.begin(), tri_offsets.end() - 1);
  for (std::size_t k = 0; k < topo_.triangles.size(); ++k)
    vertex_tris[fill[topo_.triangles[k]]++] = std::uint32_t(k / 3);
  vertex_tri_offsets_ = gl::Buffer::fromVector(tri_offsets, 0);
  vertex_tris_ = gl::Buffer::fromVector(vertex_tris, 0);
  triangles_ = gl::Buffer::fromVector(topo_.triangles, 0);
  uvs_ = gl::Buffer::fromVector(topo_.uvs, 0);

  if (scene_.sim.self_collision) allocateGrid();
}

void GpuSolver::allocateGrid() {
  const std::size_t n = std::size_t(topo_.pointCount());
  const std::size_t buckets = bucketCount();
  grid_points_ = gl::Buffer::create(n * sizeof(gpu::GridPoint), nullptr, 0);
  // Counted into with atomics, then zeroed by the scan that reads them: zero once here. The lists'
  // per-point counts use it too.
  grid_counts_ = gl::Buffer::create(std::max(buckets, n) * sizeof(std::uint32_t), nullptr, 0);
  grid_counts_.clear();
  grid_start_ = gl::Buffer::create((buckets + 1) * sizeof(std::uint32_t), nullptr, 0);
  // Shared by the bucket scan and the lists' point scan.
  grid_blocks_ = gl::Buffer::create(std::max(scanBlocks(), pointScanBlocks()) * sizeof(std::uint32_t), nullptr, 0);
  grid_scatter_ = gl::Buffer::create(n * sizeof(std::uint32_t), nullptr, 0);
  grid_sorted_ = gl::Buffer::create(n * sizeof(gpu::GridEntry), nullptr, 0);

  pair_control_ = gl::Buffer::create(sizeof(gpu::PairControl), nullptr, kUpdatable);
  pair_control_.clear();
  pair_anchor_ = gl::Buffer::create(n * sizeof(glm::vec4), nullptr, 0);
  pair_start_ = gl::Buffer::create((n + 1) * sizeof(std::uint32_t), nullptr, 0);
  allocatePairList(options_.pair_capacity ? options_.pair_capacity : pairCapacityEstimate());

  // The build's dispatch sizes; the prepare kernel copies them into `live` when the lists are stale.
  gpu::PairDispatch dispatch{};
  auto set = [&](std::uint32_t command, glm::uvec3 groups) {
    for (int k = 0; k < 3; ++k) {
      dispatch.full[3 * command + std::uint32_t(k)] = groups[k];
      dispatch.live[3 * command + std::uint32_t(k)] = groups[k];
    }
  };
  set(gpu::kPairDispatchPoints, groupsFor(n, gpu::kLocalSize));
  set(gpu::kPairDispatchOne, {1, 1, 1});
  set(gpu::kPairDispatchGridBlocks, {scanBlocks(), 1, 1});
  set(gpu::kPairDispatchPointBlocks, {pointScanBlocks(), 1, 1});
  pair_control_.upload(offsetof(gpu::PairControl, dispatch), sizeof dispatch, &dispatch);
  invalidatePairs();
}

void GpuSolver::allocatePairList(std::uint64_t capacity) {
  pair_list_ = gl::Buffer::create(capacity * sizeof(std::uint32_t), nullptr, 0);
  pair_capacity_ = capacity;
}

// The next substep rebuilds the lists: after a change of thickness or margin, or a new list buffer.
// Writes stale, travel2 and capacity; the build count and the overflow flag stay.
void GpuSolver::invalidatePairs() {
  if (pair_control_.id() == 0) return;
  const std::uint32_t stale = 1, capacity = std::uint32_t(pair_capacity_);
  const float no_travel = -1.0f;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  pair_control_.upload(offsetof(gpu::PairState, stale), sizeof stale, &stale);
  pair_control_.upload(offsetof(gpu::PairState, travel2), sizeof no_travel, &no_travel);
  pair_control_.upload(offsetof(gpu::PairState, capacity), sizeof capacity, &capacity);
}

// The same float operations as CpuSolver<float>::refreshDerived and its passes, so the kernels start
// from bit-identical constants.
void GpuSolver::uploadParams() {
  const ClothSpec& c = scene_.cloth;
  const SimParams& sim = scene_.sim;
  const WindSpec& wind = sim.wind;
  const int n = topo_.pointCount();
  const float dt = float(sim.dt());
  const float thickness = float(c.thickness);
  std::vector<gpu::PointMass> masses(std::size_t(n), gpu::PointMass{});
  for (std::size_t i = 0; i < masses.size(); ++i) {
    const float mass = float(derived::pointMass(c, topo_, i));
    masses[i].weight = glm::vec4(glm::vec3(sim.gravity) * mass, 1.0f / mass);
    masses[i].drag_area = float(derived::dragArea(wind.drag, c, topo_, i));
    const auto& stencil = topo_.normal_stencil[i];
    masses[i].normal_a = stencil[0];
    masses[i].normal_b = stencil[1];
    masses[i].normal_c = stencil[2];
    masses[i].normal_d = stencil[3];
  }
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // kernels still reading the old values come first
  point_mass_.upload(masses);
  gpu::SimParams p{};
  // A grid's points all have the same area, so the same weight: the kernels read it here instead of 48
  // bytes of PointMass per point (UNIFORM_MASS).
  if (uniformMass()) {
    p.weight = masses[0].weight;
    for (const gpu::PointMass& m : masses)
      if (m.weight != p.weight) throw std::logic_error("GpuSolver: a grid cloth's points differ in weight");
  }
  p.stiffness = glm::vec4(float(c.ks), float(c.ks), float(derived::bendingStiffness(c)), 0.0f);
  p.wind_velocity = glm::vec4(glm::vec3(wind.velocity), float(wind.turbulence));
  p.dt = dt;
  p.dt2 = dt * dt;
  p.keep = float(1.0 - c.damping / 100.0);
  p.thickness = thickness;
  p.inv_cell_size = 1.0f / (2.0f * thickness);  // as CpuSolver<float>::selfCollide rounds it
  // As CpuSolver<float>::selfCollide and CollisionPairs<float>::build compute them.
  const float range = 2.0f * thickness;
  const float margin = range * float(options_.pair_margin);
  const float reach = range + margin;
  p.inv_pair_cell = 1.0f / reach;
  p.pair_reach = reach;
  p.pair_reach2 = reach * reach;
  p.pair_margin = margin;
  p.steps_per_frame = float(sim.steps_per_frame);
  p.stretch_limit = float(sim.stretch_limit);
  p.noise_scale = float(wind.noise_scale);
  p.noise_speed = float(wind.noise_speed);
  p.sane_bound = float(options_.health.sane_bound);
  p.blow_up_stretch = float(1.0 + options_.health.max_strain);
  for (int t = 0; t < kSpringTypeCount; ++t)
    p.alpha_tilde[t] = float(derived::xpbdAlphaTilde(c, sim, SpringType(t)));
  p.point_count = std::uint32_t(n);
  p.bucket_count = bucketCount();
  p.bucket_mask = p.bucket_count - 1;
  p.scan_blocks = (p.bucket_count + gpu::kScanBlock - 1) / gpu::kScanBlock;
  params_.upload(0, sizeof p, &p);
}

// Only the enabled spring types go to the GPU, in the CPU's order (ascending spring index): a disabled
// type costs no memory traffic, and the kernels need no per-entry test.
void GpuSolver::uploadAdjacency() {
  const std::size_t n = std::size_t(topo_.pointCount());
  std::vector<std::uint32_t> offsets(n + 1, 0);
  std::vector<gpu::Neighbor> neighbors;
  neighbors.reserve(topo_.adjacency.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t e = topo_.offsets[i]; e < topo_.offsets[i + 1]; ++e) {
      const Neighbor& nb = topo_.adjacency[e];
      if (enabled_springs_[int(nb.type)])
        neighbors.push_back({nb.other | (std::uint32_t(nb.type) << gpu::kNeighborIndexBits), float(nb.rest)});
    }
    offsets[i + 1] = std::uint32_t(neighbors.size());
  }
  offsets_ = gl::Buffer::fromVector(offsets, 0);
  neighbors_ = gl::Buffer::fromVector(neighbors, 0);
  // The Gauss-Seidel stretch pass: the enabled springs in colour order, and where each colour starts.
  std::vector<gpu::ColouredSpring> coloured;
  coloured.reserve(topo_.springs.size());
  colour_start_.assign(1, 0);
  for (int c = 0; c < colouring_.colourCount(); ++c) {
    for (std::uint32_t k = colouring_.start[std::size_t(c)]; k < colouring_.start[std::size_t(c) + 1]; ++k) {
      const Spring& s = topo_.springs[colouring_.springs[k]];
      if (enabled_springs_[int(s.type)]) coloured.push_back({s.a, s.b, float(s.rest), std::uint32_t(s.type)});
    }
    colour_start_.push_back(std::uint32_t(coloured.size()));
  }
  coloured_springs_ = gl::Buffer::fromVector(coloured, 0);
}

gl::Defines GpuSolver::sceneDefines() const {
  gl::Defines d = {{"NUM_SPHERES", std::to_string(scene_.spheres.size())},
                   {"NUM_PLANES", std::to_string(scene_.planes.size())},
                   {"SELF_COLLISION", scene_.sim.self_collision ? "1" : "0"},
                   {"WIND", scene_.sim.wind.enabled ? "1" : "0"},
                   {"UNIFORM_MASS", uniformMass() ? "1" : "0"}};
  if (!scene_.meshes.empty()) d.emplace_back("NUM_MESHES", std::to_string(scene_.meshes.size()));
  if (isImplicit(scene_.sim.integrator)) d.emplace_back("PREDICT", "1");
  if (scene_.sim.integrator == Integrator::Xpbd) d.emplace_back("XPBD_LAMBDA", scene_.sim.iterations > 1 ? "1" : "0");
  if (scene_.sim.integrator == Integrator::Vbd) d.emplace_back("VBD_INERTIA", scene_.sim.iterations > 1 ? "1" : "0");
  return d;
}

// Where the collisions and the lists' travel check run: in the kernel that moved the point last.
gl::Defines GpuSolver::withFusion(gl::Defines d) const {
  const bool self = scene_.sim.self_collision, implicit = isImplicit(scene_.sim.integrator);
  d.emplace_back("COLLIDE_AFTER_INTEGRATE", hasColliders() && !self && !implicit ? "1" : "0");
  d.emplace_back("TRAVEL_CHECK", self && !implicit ? "1" : "0");
  d.emplace_back("COLLIDE_AFTER_CONTACTS", hasColliders() && self ? "1" : "0");
  return d;
}

// Kernels are compiled for this scene, so code for absent features does not exist in them. Kernels
// whose code does not depend on the scene (normals, pick) are compiled on first use.
void GpuSolver::compilePrograms() {
  defines_ = sceneDefines();
  programs_.forces_integrate = gl::compileCompute("sim/forces_integrate.comp", withFusion(defines_));
  programs_.limit_stretch = gl::compileCompute("sim/limit_stretch.comp", defines_);
  programs_.limit_stretch_coloured = gl::compileCompute("sim/limit_stretch_coloured.comp", defines_);
  programs_.health = gl::compileCompute("sim/health.comp", defines_);
  if (scene_.sim.integrator == Integrator::Xpbd)
    programs_.xpbd_coloured = gl::compileCompute("sim/xpbd_coloured.comp", defines_);
  if (scene_.sim.integrator == Integrator::Vbd)
    programs_.vbd_coloured = gl::compileCompute("sim/vbd_coloured.comp", defines_);
  if (isImplicit(scene_.sim.integrator)) {
    const bool colliders = hasColliders();
    if (colliders && !scene_.sim.self_collision) programs_.collide = gl::compileCompute("sim/collide.comp", defines_);
  }
  if (scene_.sim.self_collision) {
    programs_.pairs_check = gl::compileCompute("sim/pairs_check.comp", defines_);
    programs_.pairs_prepare = gl::compileCompute("sim/pairs_prepare.comp", defines_);
    programs_.pairs_grid_count = gl::compileCompute("sim/pairs_grid_count.comp", defines_);
    programs_.pairs_count = gl::compileCompute("sim/pairs_count.comp", defines_);
    programs_.pairs_fill = gl::compileCompute("sim/pairs_fill.comp", defines_);
    const bool one_block = pointScanBlocks() == 1;
    for (int stage = 0; stage < (one_block ? 1 : 3); ++stage) {
      gl::Defines d = defines_;
      d.emplace_back("SCAN_STAGE", std::to_string(one_block ? 3 : stage));
      d.emplace_back("PAIR_SCAN", "1");
      programs_.pairs_scan[stage] = gl::compileCompute("sim/grid_scan.comp", d);
    }
    if (gridInOneGroup()) {
      programs_.grid_build = gl::compileCompute("sim/grid_build.comp", defines_);
    } else {
      for (int stage = 0; stage < 3; ++stage) {
        gl::Defines d = defines_;
        d.emplace_back("SCAN_STAGE", std::to_string(stage));
        programs_.grid_scan[stage] = gl::compileCompute("sim/grid_scan.comp", d);
      }
      programs_.grid_scatter = gl::compileCompute("sim/grid_scatter.comp", defines_);
      programs_.grid_rank = gl::compileCompute("sim/grid_rank.comp", defines_);
    }
    gl::Defines held = defines_;
    held.emplace_back("TERMS_HELD", std::to_string(terms_held_));
    programs_.self_collide = gl::compileCompute("sim/self_collide.comp", withFusion(held));
  }
}

// Shared memory holds 12 bytes of position per point and a pin bit, and with self-collision the in-group
// grid (a bucket start per bucket, an index per point); registers hold the rest. More than a few points
// per invocation would spill registers, so a cloth needs about as many invocations as points /
// kMaxPointsPerInvocation.
namespace {
constexpr std::uint32_t kMaxPointsPerInvocation = 8;
// Blocks smaller than this copy too much ring per point they own (with a ring of 10: 12 points each).
constexpr std::uint32_t kMinStretchTile = 8;

std::uint64_t oneGroupSharedBytes(std::uint64_t points, std::uint64_t buckets, bool self_collision) {
  const std::uint64_t state = 12 * points + 4 * ((points + 31) / 32);
  return self_collision ? state + 4 * (buckets + 1) + 4 * points : state;
}
}  // namespace

// As many invocations as points up to the limit, a whole number of 32-wide warps.
std::uint32_t GpuSolver::oneGroupSize() const {
  GLint invocations = 0, size_x = 0;
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &invocations);
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 0, &size_x);
  const std::uint32_t n = std::uint32_t(topo_.pointCount());
  return std::min<std::uint32_t>((n + 31) / 32 * 32, std::uint32_t(std::min(invocations, size_x)));
}

// One bucket per invocation for the scan: the largest power of two not above the group size.
std::uint32_t GpuSolver::oneGroupBuckets() const {
  return std::bit_floor(std::max<std::uint32_t>(oneGroupSize(), 1));
}

std::string GpuSolver::oneDispatchMisfit() const {
  if (isImplicit(scene_.sim.integrator))
    return std::string("the ") + integratorName(scene_.sim.integrator) +
           " integrator runs on the general path only (one_group.comp has Verlet's phases)";
  GLint shared = 0;
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &shared);
  const std::uint64_t n = std::uint64_t(topo_.pointCount());
  const std::uint64_t need = oneGroupSharedBytes(n, oneGroupBuckets(), scene_.sim.self_collision);
  if (need > std::uint64_t(shared))
    return std::to_string(n) + " points need " + std::to_string(need) + " bytes of shared memory" +
           (scene_.sim.self_collision ? " with self-collision" : "") +
           ", more than GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (" + std::to_string(shared) + ")";
  if (n > std::uint64_t(oneGroupSize()) * kMaxPointsPerInvocation)
    return std::to_string(n) + " points are more than " + std::to_string(kMaxPointsPerInvocation) +
           " per invocation of the largest work group (" + std::to_string(oneGroupSize()) + " invocations)";
  return "";
}

// The ring a block copies is the colouring's reach (gridColourReach); the block is the largest that fits
// shared memory with it, at 12 bytes and a pin bit a point, as one_group.comp.
GpuSolver::StretchTiling GpuSolver::stretchTiling() const {
  if (!scene_.cloth.isGrid() || scene_.sim.stretch_scheme != StretchScheme::GaussSeidel) return {};
  unsigned mask = 0;
  for (int t = 0; t < kSpringTypeCount; ++t)
    if (enabled_springs_[t]) mask |= 1U << unsigned(t);
  const int reach = gridColourReach(topo_, colouring_, scene_.sim.stretch_passes, mask);
  GLint shared = 0, invocations = 0, size_x = 0;
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &shared);
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &invocations);
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 0, &size_x);
  return tilingFor(std::uint64_t(shared), std::uint64_t(std::min(invocations, size_x)), reach);
}

GpuSolver::StretchTiling GpuSolver::tilingFor(std::uint64_t shared, std::uint64_t max_group, int reach) {
  std::uint64_t region = 0;
  while (true) {
    const std::uint64_t next = region + 1, points = next * next;
    if (12 * points + 4 * ((points + 31) / 32) > std::uint64_t(shared) || points > max_group * kMaxPointsPerInvocation)
      break;
    region = next;
  }
  StretchTiling t;
  t.halo = std::uint32_t(reach);
  if (region < 2 * std::uint64_t(reach) + kMinStretchTile) return t;
  t.tile = std::uint32_t(region) - 2 * t.halo;
  t.fused_tile = t.tile >= 4 + kMinStretchTile ? t.tile - 4 : 0;
  const std::uint64_t per_group = (region * region + kMaxPointsPerInvocation - 1) / kMaxPointsPerInvocation;
  t.group_size = std::uint32_t(std::min(max_group, (per_group + 31) / 32 * 32));
  // The forces' copy: positions only, a ring of 2; the block's points are the work, 8 an invocation at most.
  std::uint64_t forces_tile = 0;
  const auto forcesFit = [&](std::uint64_t tile) {
    return 12 * (tile + 4) * (tile + 4) <= std::uint64_t(shared) && tile * tile <= max_group * kMaxPointsPerInvocation;
  };
  while (forcesFit(forces_tile + 1))
    ++forces_tile;
  t.forces_tile = std::uint32_t(forces_tile);
  const std::uint64_t forces_points = forces_tile * forces_tile;
  t.forces_group_size = std::uint32_t(
      std::min(max_group, ((forces_points + kMaxPointsPerInvocation - 1) / kMaxPointsPerInvocation + 31) / 32 * 32));
  return t;
}

// The tiled forces kernel sums springs found by grid offset with one rest length per direction, and has
// no wind; XPBD and VBD predict without springs.
bool GpuSolver::tiledForces() const {
  return tiled_ && !grid_rests_.empty() && !scene_.sim.wind.enabled && !isImplicit(scene_.sim.integrator) &&
         tiling_.forces_tile >= kMinStretchTile;
}

std::vector<float> GpuSolver::uniformGridRests() const {
  std::vector<float> rests(kGridDirectionCount, 0.0f);
  std::vector<bool> seen(kGridDirectionCount, false);
  for (const Spring& s : topo_.springs) {
    if (!enabled_springs_[int(s.type)]) continue;
    const auto d = std::size_t(gridDirection(topo_, s));
    const float rest = float(s.rest);
    if (seen[d] && rest != rests[d]) return {};
    rests[d] = rest;
    seen[d] = true;
  }
  return rests;
}

std::string GpuSolver::tiledStretchMisfit() const {
  return tiledStretchMisfit(stretchTiling());
}

std::string GpuSolver::tiledStretchMisfit(const StretchTiling& t) const {
  if (!scene_.cloth.isGrid())
    return "the tiled stretch limit needs a grid cloth (a mesh cloth's springs have no blocks)";
  if (scene_.sim.stretch_scheme != StretchScheme::GaussSeidel)
    return "the Jacobi stretch scheme is one dispatch a pass already; the tiled kernel runs the Gauss-Seidel one";
  if (t.tile < kMinStretchTile) {
    GLint shared = 0;
    glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &shared);
    return std::to_string(scene_.sim.stretch_passes) + " stretch passes reach " + std::to_string(t.halo) +
           " points around a block, too many for a block of at least " + std::to_string(kMinStretchTile) +
           " points a side in GL_MAX_COMPUTE_SHARED_MEMORY_SIZE (" + std::to_string(shared) + ")";
  }
  return "";
}

void GpuSolver::choosePath(bool constructing) {
  const std::string misfit = oneDispatchMisfit();
  if (constructing && options_.path == GpuPath::OneDispatch && !misfit.empty())
    throw GpuLimitError("gpu solver: the one-dispatch path does not fit: " + misfit);
  // The colouring's reach is worked out only where the tiled path may run.
  const bool may_tile = options_.path == GpuPath::Tiled || (options_.path == GpuPath::Auto && !context_info_.software);
  // Working out the tiling walks every spring once per stretch pass: once here, kept if the path is taken.
  const StretchTiling tiling = may_tile ? stretchTiling() : StretchTiling{};
  const std::string tiled_misfit = may_tile ? tiledStretchMisfit(tiling) : "not asked for";
  if (constructing && options_.path == GpuPath::Tiled && !tiled_misfit.empty())
    throw GpuLimitError("gpu solver: the tiled stretch limit does not apply: " + tiled_misfit);
  // Forced, either still gives way to the general path when a live change (self-collision on, a stretch
  // pass more) makes it misfit.
  one_group_ = misfit.empty() &&
               (options_.path == GpuPath::OneDispatch || (options_.path == GpuPath::Auto && !context_info_.software));
  tiled_ = !one_group_ && may_tile && tiled_misfit.empty();
  tiling_ = tiled_ ? tiling : StretchTiling{};
  grid_rests_ = (tiled_ || one_group_) && scene_.cloth.isGrid() ? uniformGridRests() : std::vector<float>{};
  // The table serves the Gauss-Seidel stretch seen from the points, where the grid cannot.
  if ((one_group_ || tiled_) && grid_rests_.empty())
    uploadColourPartners();
  else
    colour_partners_ = gl::Buffer();
  if (tiled_) {
    gl::Defines d = defines_;
    d.emplace_back("GROUP_SIZE", std::to_string(tiling_.group_size));
    d.emplace_back("TILE", std::to_string(tiling_.tile));
    d.emplace_back("HALO", std::to_string(tiling_.halo));
    d.emplace_back("GRID_SPRINGS", grid_rests_.empty() ? "0" : "1");
    programs_.limit_stretch_tiled.compile("sim/limit_stretch_tiled.comp", d);
    if (tiledForces()) {
      gl::Defines f = defines_;
      f.emplace_back("GROUP_SIZE", std::to_string(tiling_.forces_group_size));
      f.emplace_back("TILE", std::to_string(tiling_.forces_tile));
      programs_.forces_integrate_tiled.compile("sim/forces_integrate_tiled.comp", withFusion(f));
    }
  }
  // The forces need a ring of 2 stretched points around a block, so the fused copy's ring is 2 wider.
  fused_frame_ = tiledForces() && !scene_.sim.self_collision && !usesTethers() && scene_.sim.stretch_passes > 0 &&
                 tiling_.fused_tile >= kMinStretchTile;
  if (fused_frame_) {
    gl::Defines f = defines_;
    f.emplace_back("GROUP_SIZE", std::to_string(tiling_.group_size));
    f.emplace_back("TILE", std::to_string(tiling_.fused_tile));
    f.emplace_back("HALO", std::to_string(tiling_.halo + 2));
    programs_.limit_stretch_forces_tiled.compile("sim/limit_stretch_forces_tiled.comp", withFusion(f));
  }
  if (one_group_) {
    gl::Defines d = defines_;
    d.emplace_back("GROUP_SIZE", std::to_string(oneGroupSize()));
    d.emplace_back("GROUP_POINTS", std::to_string(topo_.pointCount()));
    d.emplace_back("GROUP_BUCKETS", std::to_string(oneGroupBuckets()));
    if (usesTethers()) d.emplace_back("TETHER_SLOTS", std::to_string(tether_slots_));
    if (!grid_rests_.empty()) d.emplace_back("GRID_SPRINGS", "1");
    programs_.one_group.compile("sim/one_group.comp", withFusion(d));
  }
  setPathUniforms();
}

void GpuSolver::PathProgram::compile(const char* file, const gl::Defines& with) {
  if (program.id() != 0 && with == defines) return;
  program = gl::compileCompute(file, with);
  defines = with;
}

// What stays fixed until the next path choice (a live change of parameters makes a new one) is set here
// once, not on every dispatch.
void GpuSolver::setPathUniforms() const {
  const glm::uvec2 grid(std::uint32_t(topo_.W), std::uint32_t(topo_.H));
  const auto setGrid = [&](const gl::Program& program) {
    program.setUniform("u_grid", grid);
    if (!grid_rests_.empty()) program.setUniform("u_rest", grid_rests_);
  };
  const std::uint32_t colours = std::uint32_t(colouring_.colourCount());
  const std::uint32_t passes = std::uint32_t(scene_.sim.stretch_passes);
  if (one_group_) {
    const gl::Program& program = programs_.one_group.program;
    if (!grid_rests_.empty()) setGrid(program);
    program.setUniform("u_stretch_passes", passes);
    program.setUniform("u_colours", scene_.sim.stretch_scheme == StretchScheme::GaussSeidel ? colours : 0u);
  }
  const auto setStretch = [&](const gl::Program& program) {
    setGrid(program);
    program.setUniform("u_colours", colours);
    program.setUniform("u_passes", passes);
  };
  if (tiled_) setStretch(programs_.limit_stretch_tiled.program);
  if (tiledForces()) setGrid(programs_.forces_integrate_tiled.program);
  if (fused_frame_) setStretch(programs_.limit_stretch_forces_tiled.program);
}

// Per colour and point, the point's spring of that colour (at most one: springs of a colour share no
// point), for the one-dispatch kernel's Gauss-Seidel stretch seen from each point.
void GpuSolver::uploadColourPartners() {
  const std::size_t n = std::size_t(topo_.pointCount());
  const std::size_t colours = std::size_t(colouring_.colourCount());
  std::vector<gpu::ColourPartner> partners(std::max<std::size_t>(colours * n, 1), {gpu::kNoPartner, 0.0f});
  for (std::size_t c = 0; c < colours; ++c)
    for (std::uint32_t k = colouring_.start[c]; k < colouring_.start[c + 1]; ++k) {
      const Spring& s = topo_.springs[colouring_.springs[k]];
      if (!enabled_springs_[int(s.type)]) continue;
      partners[c * n + s.a] = {s.b, float(s.rest)};
      partners[c * n + s.b] = {s.a, float(s.rest)};
    }
  colour_partners_ = gl::Buffer::fromVector(partners, 0);
}

void GpuSolver::setParams(const ClothSpec& cloth, const SimParams& sim) {
  applyLiveParams(scene_, cloth, sim);
  bool springs_changed = false;
  for (int t = 0; t < kSpringTypeCount; ++t) {
    const bool enabled = scene_.cloth.springEnabled(SpringType(t));
    springs_changed |= enabled != enabled_springs_[t];
    enabled_springs_[t] = enabled;
  }
  checkLimits();
  if (springs_changed) uploadAdjacency();
  allocateLambda();
  allocateVbd();
  allocateTethers();
  if (scene_.sim.self_collision && grid_points_.id() == 0) allocateGrid();
  uploadParams();
  invalidatePairs();  // thickness may have changed, and with it the lists' reach
  if (sceneDefines() != defines_) compilePrograms();
  choosePath(false);        // self-collision or the spring types may have changed whether it fits
  buildPlan();              // stretch passes, scheme and spring types change what a substep dispatches
  health_checked_ = false;  // the spring types checked may have changed
}

}  // namespace drape
