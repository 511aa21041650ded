// GpuSolver: the substep as a list of dispatches, the state's ping-pong, timing and read-back.
#include "core/tethers.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu/layout.hpp"

static_assert(drape::gpu::kHealthNonFinite == drape::Health::kNonFinite &&
              drape::gpu::kHealthOutOfBounds == drape::Health::kOutOfBounds &&
              drape::gpu::kHealthOverstretched == drape::Health::kOverstretched);

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>

namespace drape {

namespace {

// The phases of one_group.comp's substep (u_phases).
constexpr std::uint32_t kIntegratePhase = gpu::kPhaseIntegrate, kStretchPhase = gpu::kPhaseStretch,
                        kSelfCollidePhase = gpu::kPhaseSelfCollide, kTetherPhase = gpu::kPhaseTether;
constexpr std::uint32_t kAllPhases = gpu::kPhaseAll;

// What the frame-end copy writes into each slot of the health ring.
struct HealthSnapshot {
  gpu::Health health;
  gpu::PairState pairs;
};
static_assert(sizeof(HealthSnapshot) == sizeof(gpu::Health) + sizeof(gpu::PairState), "the ring's size (allocate())");

// The state a point, as the buffers lay it out: bytesPerPoint counts these.
constexpr double kPosition = sizeof(glm::vec4);      // w: the pin flag
constexpr double kDisplacement = sizeof(glm::vec3);  // packed
constexpr double kState = kPosition + kDisplacement;

}  // namespace

void GpuSolver::step() {
  timing_break_ = true;
  if (one_group_) {
    runOneGroup(1, kAllPhases, false);
  } else {
    bindShared();
    for (const PlannedDispatch& d : plan_)
      run(d);
  }
  ++substeps_;
  health_checked_ = false;
}

void GpuSolver::stepFrame() {
  timing_break_ = true;
  const int substeps = scene_.sim.steps_per_frame;
  if (one_group_) {
    runOneGroup(std::uint32_t(substeps), kAllPhases, true);  // the health check too: the whole frame is one dispatch
    substeps_ += substeps;
    health_checked_ = true;
    snapshotHealth();
    return;
  }
  bindShared();
  // The fused kernel runs the previous substep's stretch limit before its forces; the frame's first
  // substep has none before it.
  const gl::Program& fused = programs_.limit_stretch_forces_tiled.program;
  if (fused_frame_) fused.setUniform("u_stretch", false);
  for (int s = 0; s < substeps; ++s) {
    for (const PlannedDispatch& d : frame_.substep)
      run(d);
    ++substeps_;  // wind's time
    if (fused_frame_ && s == 0) fused.setUniform("u_stretch", true);
  }
  for (const PlannedDispatch& d : frame_.tail)
    run(d);
  health_checked_ = false;
  endFrame();
}

void GpuSolver::runOneGroup(std::uint32_t substeps, std::uint32_t phases, bool check_health) {
  bindShared();
  const gl::Program& program = programs_.one_group.program;
  if (grid_rests_.empty()) colour_partners_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingColourPartners);
  if (usesTethers()) tethers_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingTethers);
  program.setUniform("u_substeps", substeps);
  program.setUniform("u_phases", phases);
  program.setUniform("u_check_health", check_health);
  if (scene_.sim.wind.enabled) {
    program.setUniform("u_first_substep", double(substeps_));
    program.setUniform("u_dt", scene_.sim.dt());
  }
  // In place: the work group reads the whole state before it writes any of it.
  bindState(current_, 1 - current_);
  dispatch(kOneGroup, program, {1, 1, 1});
}

void GpuSolver::forcesIntegrate() {
  runStageOrPhase(Stage::Integrate, kIntegratePhase);
}

void GpuSolver::selfCollide() {
  runStageOrPhase(Stage::SelfCollide, kSelfCollidePhase);
}

void GpuSolver::limitStretch() {
  runStageOrPhase(Stage::Stretch, kStretchPhase);
}

void GpuSolver::solveXpbd() {
  runStage(Stage::Xpbd);
}

void GpuSolver::solveVbd() {
  runStage(Stage::Vbd);
}

void GpuSolver::collide() {
  runStage(Stage::Collide);
}

void GpuSolver::tether() {
  runStageOrPhase(Stage::Tether, kTetherPhase);
}

void GpuSolver::runStageOrPhase(Stage stage, std::uint32_t phase) {
  if (one_group_)
    runOneGroup(1, phase, false);
  else
    runStage(stage);
}

void GpuSolver::runStage(Stage stage) {
  bindShared();
  for (const PlannedDispatch& d : plan_)
    if (d.stage == stage) run(d);
}

void GpuSolver::buildPlan() {
  planSubstep();
  // The fused frame cuts the substeps' passes differently, in their own order: each substep's stretch
  // limit with the next one's forces (limit_stretch_forces_tiled.comp), then the last one's stretch limit.
  if (fused_frame_) {
    frame_.substep = {{kLimitStretchForcesTiled, Stage::Integrate, &programs_.limit_stretch_forces_tiled.program,
                       PlannedDispatch::Size::Tiles, true}};
    frame_.tail = {plan_.back()};  // limit_stretch_tiled
  } else {
    frame_.substep = plan_;
    frame_.tail.clear();
  }
}

void GpuSolver::planSubstep() {
  using Size = PlannedDispatch::Size;
  plan_.clear();
  const auto add = [this](PassId pass, Stage stage, const gl::Program& program, Size size, bool ping_pong,
                          std::uint32_t command = 0) {
    plan_.push_back({pass, stage, &program, size, ping_pong, command});
  };
  // One dispatch per colour with springs, each over that colour's range of the coloured springs.
  const auto addColours = [&](PassId pass, Stage stage, const gl::Program& program, std::uint32_t sweep) {
    for (std::size_t c = 0; c + 1 < colour_start_.size(); ++c) {
      const std::uint32_t count = colour_start_[c + 1] - colour_start_[c];
      if (count == 0) continue;
      add(pass, stage, program, Size::Springs, false);
      plan_.back().first = colour_start_[c];
      plan_.back().count = count;
      plan_.back().sweep = sweep;
    }
  };
  // VBD: one dispatch per point colour, each over that colour's range of the coloured points.
  const auto addPointColours = [&](std::uint32_t sweep) {
    for (std::size_t c = 0; c + 1 < point_colour_start_.size(); ++c) {
      add(kVbdColoured, Stage::Vbd, programs_.vbd_coloured, Size::ColourPoints, false);
      plan_.back().first = point_colour_start_[c];
      plan_.back().count = point_colour_start_[c + 1] - point_colour_start_[c];
      plan_.back().sweep = sweep;
    }
  };
  if (one_group_) {  // the frame's one dispatch (runOneGroup), not a list per substep
    add(kOneGroup, Stage::Integrate, programs_.one_group.program, Size::One, false);
    return;
  }
  if (tiledForces())
    add(kForcesIntegrateTiled, Stage::Integrate, programs_.forces_integrate_tiled.program, Size::Tiles, true);
  else
    add(kForcesIntegrate, Stage::Integrate, programs_.forces_integrate, Size::Points, true);
  const bool implicit = isImplicit(scene_.sim.integrator);
  if (implicit) {
    // In place, as the Gauss-Seidel stretch pass below (CpuSolver::solveXpbd, solveVbd).
    for (int sweep = 0; sweep < scene_.sim.iterations; ++sweep) {
      if (scene_.sim.integrator == Integrator::Xpbd)
        addColours(kXpbdColoured, Stage::Xpbd, programs_.xpbd_coloured, std::uint32_t(sweep));
      else
        addPointColours(std::uint32_t(sweep));
    }
    if (hasColliders() && !scene_.sim.self_collision)
      add(kCollide, Stage::Collide, programs_.collide, Size::Points, true);
  }
  // The candidate lists are rebuilt on the GPU's own decision (pairs_prepare writes the build's indirect
  // dispatch sizes), so no read-back stalls the substep; when the lists are fresh, the build's dispatches
  // run zero work groups.
  if (scene_.sim.self_collision) {
    const Stage stage = Stage::SelfCollide;
    add(kPairsCheck, stage, programs_.pairs_check, Size::Points, false);
    plan_.back().unless_checked = !implicit;  // the prediction does not check: the sweeps move the points after it
    add(kPairsPrepare, stage, programs_.pairs_prepare, Size::One, false);
    plan_.back().writes_commands = true;
    add(kPairsGridCount, stage, programs_.pairs_grid_count, Size::Indirect, false, gpu::kPairDispatchPoints);
    if (gridInOneGroup()) {
      add(kGridBuild, stage, programs_.grid_build, Size::Indirect, false, gpu::kPairDispatchOne);
    } else {
      add(kGridScan, stage, programs_.grid_scan[0], Size::Indirect, false, gpu::kPairDispatchGridBlocks);
      add(kGridScanBlocks, stage, programs_.grid_scan[1], Size::Indirect, false, gpu::kPairDispatchOne);
      add(kGridScanOffsets, stage, programs_.grid_scan[2], Size::Indirect, false, gpu::kPairDispatchGridBlocks);
      add(kGridScatter, stage, programs_.grid_scatter, Size::Indirect, false, gpu::kPairDispatchPoints);
      add(kGridRank, stage, programs_.grid_rank, Size::Indirect, false, gpu::kPairDispatchPoints);
    }
    add(kPairsCount, stage, programs_.pairs_count, Size::Indirect, false, gpu::kPairDispatchPoints);
    if (pointScanBlocks() == 1) {
      add(kPairsScan, stage, programs_.pairs_scan[0], Size::Indirect, false, gpu::kPairDispatchOne);
    } else {
      add(kPairsScan, stage, programs_.pairs_scan[0], Size::Indirect, false, gpu::kPairDispatchPointBlocks);
      add(kPairsScanBlocks, stage, programs_.pairs_scan[1], Size::Indirect, false, gpu::kPairDispatchOne);
      add(kPairsScanOffsets, stage, programs_.pairs_scan[2], Size::Indirect, false, gpu::kPairDispatchPointBlocks);
    }
    add(kPairsFill, stage, programs_.pairs_fill, Size::Indirect, false, gpu::kPairDispatchPoints);
    add(kSelfCollide, stage, programs_.self_collide, Size::Points, true);
  }
  // In place: a point writes only itself and reads only anchors, which are pinned.
  if (usesTethers()) add(kTether, Stage::Tether, programs_.tether, Size::Points, false);
  if (tiled_) {  // every colour of every pass in the one dispatch, blocks in shared memory
    if (scene_.sim.stretch_passes > 0)
      add(kLimitStretchTiled, Stage::Stretch, programs_.limit_stretch_tiled.program, Size::Tiles, true);
    return;
  }
  for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass) {
    if (scene_.sim.stretch_scheme == StretchScheme::Jacobi) {
      add(kLimitStretch, Stage::Stretch, programs_.limit_stretch, Size::Points, true);
      continue;
    }
    // In place on the current state: the springs of one colour share no point, and the storage barrier
    // after each dispatch lets the next colour see the moved points (CpuSolver::limitStretchColoured).
    addColours(kLimitStretchColoured, Stage::Stretch, programs_.limit_stretch_coloured, 0);
  }
}

void GpuSolver::run(const PlannedDispatch& d) {
  if (d.unless_checked && pairs_checked_) return;
  const gl::Program& program = *d.program;
  if (d.pass == kForcesIntegrate && scene_.sim.wind.enabled)
    program.setUniform("u_time", float(double(substeps_) * scene_.sim.dt()));
  if (d.size == PlannedDispatch::Size::Springs) {
    coloured_springs_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingColouredSprings);
    program.setUniform("u_first", d.first);
    program.setUniform("u_count", d.count);
  }
  if (d.pass == kTether) tethers_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingTethers);
  if (d.pass == kLimitStretchTiled && grid_rests_.empty())
    colour_partners_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingColourPartners);
  if (d.pass == kXpbdColoured && scene_.sim.iterations > 1) {
    xpbd_lambda_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingXpbdLambda);
    program.setUniform("u_sweep", d.sweep);
  }
  if (d.size == PlannedDispatch::Size::ColourPoints) {
    coloured_points_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingColouredPoints);
    program.setUniform("u_first", d.first);
    program.setUniform("u_count", d.count);
    if (scene_.sim.iterations > 1) {
      vbd_inertia_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingVbdInertia);
      program.setUniform("u_sweep", d.sweep);
    }
  }
  bindState(current_, 1 - current_);
  switch (d.size) {
    case PlannedDispatch::Size::Points:
      dispatch(d.pass, program, groupsFor(std::uint64_t(topo_.pointCount()), gpu::kLocalSize));
      break;
    case PlannedDispatch::Size::One:
      dispatch(d.pass, program, {1, 1, 1});
      break;
    case PlannedDispatch::Size::Springs:
    case PlannedDispatch::Size::ColourPoints:
      dispatch(d.pass, program, groupsFor(d.count, gpu::kLocalSize));
      break;
    case PlannedDispatch::Size::Indirect:
      dispatchIndirect(d.pass, program, d.command);
      break;
    case PlannedDispatch::Size::Tiles: {
      const std::uint32_t tile = d.pass == kForcesIntegrateTiled      ? tiling_.forces_tile
                                 : d.pass == kLimitStretchForcesTiled ? tiling_.fused_tile
                                                                      : tiling_.tile;
      dispatch(d.pass, program, {tileCount(topo_.W, tile), tileCount(topo_.H, tile), 1});
      break;
    }
  }
  if (d.ping_pong) current_ = 1 - current_;
  if (d.writes_commands) glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
  // Integrate checks the travel for the lists when self-collision follows; self-collision consumes it.
  if (d.pass == kForcesIntegrate || d.pass == kForcesIntegrateTiled)
    pairs_checked_ = scene_.sim.self_collision && !isImplicit(scene_.sim.integrator);
  if (d.pass == kSelfCollide) pairs_checked_ = false;
}

double GpuSolver::bytesPerPoint(const PlannedDispatch& d) const {
  const double n = double(topo_.pointCount());
  // Bytes loaded and stored: a gather as often as it is issued; a tiled kernel's copy once per work group
  // (a ring copied by two groups twice), and what the group reads again of what it copied not at all.
  constexpr double kRange = 2 * sizeof(std::uint32_t);
  const double entries = double(neighbors_.size() / sizeof(gpu::Neighbor)) / n;  // springs seen from a point
  const double candidates = double(pair_entries_) / n;
  switch (d.pass) {
    case kForcesIntegrate: {  // own state and point data, the adjacency, each neighbour's position; new state
      // A grid's weight comes from the parameters; the point data only for wind (normal stencil, drag).
      const double point = uniformMass() && !scene_.sim.wind.enabled ? 0 : sizeof(gpu::PointMass);
      return kState + point + kRange + entries * (sizeof(gpu::Neighbor) + sizeof(glm::vec4)) + kState;
    }
    case kForcesIntegrateTiled:  // every copied point's position; a block point's displacement; new state
      return copiedPerPoint(topo_.W, topo_.H, tiling_.forces_tile, 2) * kPosition + kDisplacement + kState;
    case kLimitStretch:  // the same gather (each neighbour's pin flag rides in its position's w)
      return kState + kRange + entries * (sizeof(gpu::Neighbor) + sizeof(glm::vec4)) + kState;
    case kLimitStretchColoured:  // per spring: the entry, both ends' state read and written
      return double(d.count) * (sizeof(gpu::ColouredSpring) + 4 * kState) / n;
    case kLimitStretchTiled: {  // every copied point's position and, per colour and pass, its table entry
                                // (none where the grid gives partners and rests); a block point's
                                // displacement; the block's new state
      const double copied = copiedPerPoint(topo_.W, topo_.H, tiling_.tile, tiling_.halo);
      const double table = grid_rests_.empty() ? double(scene_.sim.stretch_passes) * colouring_.colourCount() *
                                                     sizeof(gpu::ColourPartner)
                                               : 0.0;
      return copied * (kPosition + table) + kDisplacement + kState;
    }
    case kLimitStretchForcesTiled:
      return fusedBytesPerPoint(topo_.W, topo_.H, tiling_);
    case kOneGroup: {  // per substep: the adjacency, the stretch table; the state once per frame
      // Positions are gathered from shared memory, not device memory; self-collision's grid lives there too. The state
      // (and the weight, kept in registers) is read and written once per dispatch, a frame of steps_per_frame substeps.
      // A flat grid's springs come from the grid (GRID_SPRINGS): no adjacency, no table.
      const bool grid = !grid_rests_.empty();
      const double frame = kState + sizeof(glm::vec4) + kState;
      double substep = grid ? 0 : kRange + entries * sizeof(gpu::Neighbor);
      if (scene_.sim.wind.enabled) substep += sizeof(gpu::PointMass);
      const bool coloured = scene_.sim.stretch_scheme == StretchScheme::GaussSeidel;
      const double stretch = !coloured ? kRange + entries * sizeof(gpu::Neighbor)
                             : grid    ? 0
                                       : colouring_.colourCount() * sizeof(gpu::ColourPartner);
      const double tethers = usesTethers() ? tether_slots_ * sizeof(gpu::Tether) : 0;  // anchors: shared memory
      return frame / scene_.sim.steps_per_frame + substep + tethers + scene_.sim.stretch_passes * stretch;
    }
    case kXpbdColoured:  // per spring: the entry, both ends' state and inverse mass read, state written
      return double(d.count) *
             (sizeof(gpu::ColouredSpring) + 4 * kState + 2 * sizeof(gpu::PointMass) +
              (scene_.sim.iterations > 1 ? 2 * sizeof(float) : 0)) /
             n;
    case kVbdColoured: {  // per point of the colour: its index, state, weight, adjacency, neighbours; state written
      const double weight = uniformMass() ? 0 : sizeof(gpu::PointMass);
      const double inertia = scene_.sim.iterations > 1 ? sizeof(glm::vec4) : 0;  // y written, or read
      return double(d.count) *
             (sizeof(std::uint32_t) + 2 * kState + weight + inertia + kRange +
              entries * (sizeof(gpu::Neighbor) + sizeof(glm::vec4))) /
             n;
    }
    case kCollide:  // own state read and written
      return 2 * kState;
    case kTether:  // own state, each slot's entry and anchor position; own state written
      return kState + tether_slots_ * (sizeof(gpu::Tether) + sizeof(glm::vec4)) + kState;
    case kSelfCollide:  // own state, the list, each candidate's position; new state
      return kState + kRange + candidates * (sizeof(std::uint32_t) + sizeof(glm::vec4)) + kState;
    default:  // pairs_prepare: one invocation; the list build: zero work groups while the lists are fresh
      return 0;
  }
}

std::uint32_t GpuSolver::tileCount(int points, std::uint32_t tile) {
  return (std::uint32_t(points) + tile - 1) / tile;
}

// Blocks along one edge, each with its ring clipped to the cloth: the rows (or columns) of points copied.
std::uint64_t GpuSolver::copiedPoints(int points, std::uint32_t tile, std::uint32_t ring) {
  std::uint64_t total = 0;
  for (std::uint32_t b = 0; b < tileCount(points, tile); ++b) {
    const std::int64_t lo = std::int64_t(b) * tile, hi = std::min<std::int64_t>(lo + tile, points);
    total += std::uint64_t(std::min<std::int64_t>(hi + ring, points) - std::max<std::int64_t>(lo - ring, 0));
  }
  return total;
}

// Points copied into shared memory per cloth point, by blocks of `tile` with rings of `ring` over W x H.
double GpuSolver::copiedPerPoint(int W, int H, std::uint32_t tile, std::uint32_t ring) {
  return double(copiedPoints(W, tile, ring)) * double(copiedPoints(H, tile, ring)) / (double(W) * double(H));
}

double GpuSolver::fusedBytesPerPoint(int W, int H, const StretchTiling& tiling) {
  // Every copied point's position (a ring of the reach + 2); a block point's displacement; the new state.
  return copiedPerPoint(W, H, tiling.fused_tile, tiling.halo + 2) * kPosition + kDisplacement + kState;
}

double GpuSolver::bytesPerPointPerSubstep() const {
  double substep = 0, tail = 0;
  for (const PlannedDispatch& d : frame_.substep)
    if (!d.unless_checked) substep += bytesPerPoint(d);
  for (const PlannedDispatch& d : frame_.tail)
    tail += bytesPerPoint(d);
  return substep + tail / scene_.sim.steps_per_frame;
}

std::vector<std::string> GpuSolver::passes() const {
  std::vector<std::string> out;
  if (one_group_) {  // the phases of the one dispatch, each substep
    const bool colliders = hasColliders();
    const bool self = scene_.sim.self_collision;
    out.push_back(std::string("in-group forces+integrate") + (colliders && !self ? "+collide" : ""));
    if (self) out.push_back(std::string("in-group self_collide") + (colliders ? "+collide" : ""));
    if (usesTethers()) out.push_back(std::string("in-group ") + kTetherPassName);
    const bool coloured = scene_.sim.stretch_scheme == StretchScheme::GaussSeidel;
    for (int pass = 0; pass < scene_.sim.stretch_passes; ++pass)
      for (int c = 0; c < (coloured ? colouring_.colourCount() : 1); ++c)
        out.push_back(coloured ? "in-group limit_stretch_colour" : "in-group limit_stretch");
    return out;
  }
  for (const PlannedDispatch& d : frame_.substep)
    if (!d.unless_checked) out.push_back(passName(d.pass));
  return out;
}

int GpuSolver::dispatchesPerFrame() const {
  if (one_group_) return 1;
  return int(passes().size()) * scene_.sim.steps_per_frame + int(framePasses().size());
}

double GpuSolver::dispatchesPerSubstep() const {
  if (one_group_) return 1.0 / double(scene_.sim.steps_per_frame);
  const double substeps = scene_.sim.steps_per_frame;
  return (double(passes().size()) * substeps + double(frame_.tail.size())) / substeps;
}

std::string GpuSolver::passName(PassId pass) const {
  const bool colliders = hasColliders();
  switch (pass) {
    case kForcesIntegrateTiled:
      return std::string("forces_tiled+integrate") + (scene_.sim.self_collision ? "+pairs_check"
                                                      : colliders               ? "+collide"
                                                                                : "");
    case kForcesIntegrate:
      if (isImplicit(scene_.sim.integrator)) return "forces+predict";
      return std::string("forces+integrate") + (scene_.sim.self_collision ? "+pairs_check"
                                                : colliders               ? "+collide"
                                                                          : "");
    case kPairsCheck:
      return "pairs_check";
    case kPairsPrepare:
      return "pairs_prepare";
    case kPairsGridCount:
      return "pairs_grid_count";
    case kPairsCount:
      return "pairs_count";
    case kPairsScan:
      return "pairs_scan";
    case kPairsScanBlocks:
      return "pairs_scan_blocks";
    case kPairsScanOffsets:
      return "pairs_scan_offsets";
    case kPairsFill:
      return "pairs_fill";
    case kGridBuild:
      return "grid_build";
    case kGridScan:
      return "grid_scan";
    case kGridScanBlocks:
      return "grid_scan_blocks";
    case kGridScanOffsets:
      return "grid_scan_offsets";
    case kGridScatter:
      return "grid_scatter";
    case kGridRank:
      return "grid_rank";
    case kSelfCollide:
      return colliders ? "self_collide+collide" : "self_collide";
    case kLimitStretch:
      return "limit_stretch";
    case kLimitStretchColoured:
      return "limit_stretch_colour";
    case kLimitStretchTiled:
      return "limit_stretch_tiled";
    case kLimitStretchForcesTiled:
      return std::string("limit_stretch_forces_tiled+integrate") + (colliders ? "+collide" : "");
    case kOneGroup:
      return "one_group";
    case kXpbdColoured:
      return "xpbd_colour";
    case kVbdColoured:
      return "vbd_colour";
    case kCollide:
      return "collide";
    case kTether:
      return kTetherPassName;
    case kNormals:
      return "normals";
    case kPick:
      return "pick";
    case kHealth:
      return "health";
    case kPassCount:
      break;
  }
  return "?";
}

// The renderer (or anything else) may bind its own buffers to the same indices between our calls, so
// every stage binds what it uses; a binding is a cheap state change.
void GpuSolver::bindShared() const {
  params_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingParams);
  point_mass_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPointMass);
  offsets_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingOffsets);
  neighbors_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingNeighbors);
  colliders_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingColliders);
  health_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingHealth);
  if (grid_points_.id() != 0) {
    grid_points_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridPoints);
    grid_counts_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridCounts);
    grid_start_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridStart);
    grid_blocks_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridBlocks);
    grid_scatter_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridScatter);
    grid_sorted_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingGridSorted);
    pair_control_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPairControl);
    pair_anchor_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPairAnchor);
    pair_start_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPairStart);
    pair_list_.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPairList);
  }
}

void GpuSolver::bindState(int in, int out) const {
  state_[in].position.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPosIn);
  state_[in].displacement.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingDispIn);
  state_[out].position.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingPosOut);
  state_[out].displacement.bindBase(GL_SHADER_STORAGE_BUFFER, gpu::kBindingDispOut);
}

// Work groups covering `invocations`, spread over y when x alone would pass the guaranteed limit
// (the kernels fold the 2D index back, see globalIndex() in glsl/sim/common.glsl).
glm::uvec3 GpuSolver::groupsFor(std::uint64_t invocations, std::uint32_t local_size) const {
  const std::uint64_t groups = std::max<std::uint64_t>((invocations + local_size - 1) / local_size, 1);
  if (groups <= max_groups_x_) return {std::uint32_t(groups), 1, 1};
  const std::uint64_t rows = (groups + max_groups_x_ - 1) / max_groups_x_;
  return {max_groups_x_, std::uint32_t(rows), 1};
}

void GpuSolver::dispatch(PassId pass, const gl::Program& program, glm::uvec3 groups) {
  timed(pass, [&] { program.dispatch(groups); });
}

void GpuSolver::dispatchIndirect(PassId pass, const gl::Program& program, std::uint32_t command) {
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pair_control_.id());
  const std::size_t offset =
      offsetof(gpu::PairControl, dispatch) + offsetof(gpu::PairDispatch, live) + 3 * command * sizeof(std::uint32_t);
  timed(pass, [&] { program.dispatchIndirect(offset); });
}

template <class F>
void GpuSolver::timed(PassId pass, F&& run) {
  PassTiming& timing = timings_[pass];
  ++timing.calls;
  if (!options_.timing) {
    run();
  } else if (timer_queries_) {
    // A GPU timestamp after each dispatch: a pass takes the time since the timestamp before it. Nothing
    // waits: the results are collected once the GPU has them (resolveQueries).
    // A new start where the host may have paused between dispatches (a substep, the normals before a
    // draw), so that the pause is not counted as the next pass's time.
    if (pending_.empty() || timing_break_) pending_.push_back({kPassCount, takeQuery()});
    timing_break_ = false;
    run();
    pending_.push_back({pass, takeQuery()});
    if (pending_.size() >= 4096) resolveQueries(true);  // bounded memory; results are ready long before
  } else {
    // No GPU timer (llvmpipe): wall clock around the dispatch, with the pipeline drained on both sides.
    gl::finish();
    const auto start = std::chrono::steady_clock::now();
    run();
    gl::finish();
    timing.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  // Every later pass reads through SSBOs what this one wrote. Shader storage writes are incoherent:
  // without this barrier the next dispatch may still read the old values.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

gl::Query GpuSolver::takeQuery() {
  gl::Query query;
  if (spare_queries_.empty()) {
    query = gl::Query::create(GL_TIMESTAMP);
  } else {
    query = std::move(spare_queries_.back());
    spare_queries_.pop_back();
  }
  query.timestamp();
  return query;
}

// Timestamps arrive in order, so the available ones are a prefix of pending_. The last one stays as the
// start of the passes after it.
void GpuSolver::resolveQueries(bool wait) const {
  std::size_t done = 0;
  while (done + 1 < pending_.size() && (wait || pending_[done + 1].query.resultAvailable())) {
    const PendingQuery& before = pending_[done];
    const PendingQuery& after = pending_[done + 1];
    if (after.pass != kPassCount)
      timings_[after.pass].ms += double(after.query.result() - before.query.result()) * 1e-6;
    ++done;
  }
  for (std::size_t i = 0; i < done; ++i)
    spare_queries_.push_back(std::move(pending_[i].query));
  pending_.erase(pending_.begin(), pending_.begin() + std::ptrdiff_t(done));
}

std::vector<PassTiming> GpuSolver::timings() const {
  resolveQueries(false);
  std::vector<PassTiming> out;
  for (int p = 0; p < kPassCount; ++p) {
    if (timings_[p].calls == 0) continue;
    out.push_back(timings_[p]);
    out.back().name = passName(PassId(p));
  }
  return out;
}

void GpuSolver::resetTimings() {
  resolveQueries(false);
  timings_.assign(kPassCount, PassTiming{});
  for (int p = 0; p < kPassCount; ++p)
    timings_[p].name = passName(PassId(p));
}

void GpuSolver::reset() {
  const std::size_t n = std::size_t(topo_.pointCount());
  std::vector<glm::vec4> x(n);
  const std::vector<glm::vec3> v(n, glm::vec3(0.0f));
  for (std::size_t i = 0; i < n; ++i)
    x[i] = glm::vec4(glm::vec3(topo_.initial_positions[i]), topo_.pinned[i] ? 1.0f : 0.0f);
  // Uploads must not overtake shader writes still in flight to the same buffers.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  current_ = 0;
  state_[0].position.upload(x);
  state_[0].displacement.upload(v);
  substeps_ = 0;
  held_ = -1;
  pairs_checked_ = false;
  clearHealth();
}

void GpuSolver::uploadState(const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& v, long long substeps) {
  const std::size_t n = std::size_t(topo_.pointCount());
  if (x.size() != n || v.size() != n)
    throw std::invalid_argument("GpuSolver::uploadState: expected " + std::to_string(n) + " points");
  std::vector<glm::vec4> px(n);
  std::vector<glm::vec3> pv(n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool pinned = topo_.pinned[i] != 0 || int(i) == held_;
    px[i] = glm::vec4(glm::vec3(x[i]), pinned ? 1.0f : 0.0f);
    pv[i] = glm::vec3(v[i]);
  }
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  state_[current_].position.upload(px);
  state_[current_].displacement.upload(pv);
  substeps_ = substeps;
  pairs_checked_ = false;
  health_checked_ = false;
}

std::vector<glm::dvec3> GpuSolver::readPositions() {
  // glGetBufferSubData after shader writes needs this barrier to see them.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const auto x = state_[current_].position.download<glm::vec4>(std::size_t(topo_.pointCount()));
  std::vector<glm::dvec3> out(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    out[i] = glm::dvec3(glm::vec3(x[i]));
  return out;
}

std::vector<glm::dvec3> GpuSolver::readDisplacements() {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const auto v = state_[current_].displacement.download<glm::vec3>(std::size_t(topo_.pointCount()));
  std::vector<glm::dvec3> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = glm::dvec3(v[i]);
  return out;
}

GpuGrid GpuSolver::readGrid() {
  GpuGrid grid;
  if (grid_points_.id() == 0) return grid;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const std::size_t n = std::size_t(topo_.pointCount());
  for (const gpu::GridPoint& g : grid_points_.download<gpu::GridPoint>(n)) {
    grid.cells.emplace_back(g.cell_x, g.cell_y, g.cell_z);
    grid.buckets.push_back(g.bucket);
    grid.arrival.push_back(g.arrival);
  }
  grid.start = grid_start_.download<std::uint32_t>(std::size_t(bucketCount()) + 1);
  for (const gpu::GridEntry& e : grid_sorted_.download<gpu::GridEntry>(n)) {
    grid.sorted.push_back(e.index);
    grid.sorted_anchor.emplace_back(e.x, e.y, e.z);
  }
  return grid;
}

GpuPairs GpuSolver::readPairs() {
  GpuPairs pairs;
  if (pair_control_.id() == 0) return pairs;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const gpu::PairState state = pair_control_.download<gpu::PairState>(1)[0];
  pairs.capacity = state.capacity;
  pairs.builds = state.builds;
  pairs.overflow = state.overflow != 0;
  pairs.travel2 = state.travel2;
  pairs.start = pair_start_.download<std::uint32_t>(std::size_t(topo_.pointCount()) + 1);
  pairs.list = pair_list_.download<std::uint32_t>(std::min<std::size_t>(pairs.start.back(), state.capacity));
  return pairs;
}

// When a list build needed more entries than the buffer holds, a buffer 1.5x that size replaces it and
// the lists are rebuilt. Until then the points that did not fit were served from the grid, with the same
// result. `state` comes from a read-back (health()) or a frame's snapshot (recentHealth()); a snapshot
// older than the last growth asks for no more than the buffer now holds, so it changes nothing.
void GpuSolver::growPairList(const gpu::PairState& state) {
  if (pair_control_.id() == 0 || state.overflow == 0) return;
  const std::uint64_t limit = maxBufferBytes() / sizeof(std::uint32_t);
  const std::uint64_t wanted = std::min(std::uint64_t(state.total) + state.total / 2, limit);
  if (wanted <= pair_capacity_) return;  // grown already, or as large as allowed: the grid serves the rest
  const std::uint32_t clear = 0;
  pair_control_.upload(offsetof(gpu::PairState, overflow), sizeof clear, &clear);
  allocatePairList(wanted);
  invalidatePairs();
}

// After the frame's last pass, so that a state made bad by any pass (self-collision, the stretch limit)
// is reported in the frame that made it. Binds the current state as input and writes only the flags.
void GpuSolver::checkHealth() {
  bindShared();
  bindState(current_, 1 - current_);
  dispatch(kHealth, programs_.health, groupsFor(std::uint64_t(topo_.pointCount()), gpu::kLocalSize));
  health_checked_ = true;
}

Health GpuSolver::health() {
  if (!health_checked_) checkHealth();
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (pair_control_.id() != 0) {
    const gpu::PairState state = pair_control_.download<gpu::PairState>(1)[0];
    pair_entries_ = state.total;
    growPairList(state);
  }
  const gpu::Health h = health_.download<gpu::Health>(1)[0];
  Health out;
  out.flags = h.flags;
  out.first_point = h.flags != 0 ? (long long)h.first_point : -1;
  out.substeps = substeps_;
  return out;
}

void GpuSolver::endFrame() {
  checkHealth();
  snapshotHealth();
}

void GpuSolver::snapshotHealth() {
  newest_slot_ = (newest_slot_ + 1) % kHealthSlots;
  HealthSlot& slot = health_slots_[newest_slot_];
  // The slot's previous fence signalled long ago (it is two frames old); waiting on it keeps the
  // mapped bytes from being overwritten while a reader could still look at them.
  slot.fence.wait();
  const std::size_t at = std::size_t(newest_slot_) * sizeof(HealthSnapshot);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // the copies read what the kernels wrote
  health_.copyTo(health_ring_, 0, at + offsetof(HealthSnapshot, health), sizeof(gpu::Health));
  if (pair_control_.id() != 0)
    pair_control_.copyTo(health_ring_, offsetof(gpu::PairControl, state), at + offsetof(HealthSnapshot, pairs),
                         sizeof(gpu::PairState));
  slot.fence = gl::Fence::insert();
  slot.substeps = substeps_;
}

void GpuSolver::forgetSnapshots() {
  for (HealthSlot& slot : health_slots_) {
    slot.fence.wait();  // a copy still in flight would land in a slot read as fresh
    slot = HealthSlot{};
  }
  newest_slot_ = -1;
}

Health GpuSolver::recentHealth() {
  if (newest_slot_ < 0) return health();  // no frame ended since the reset: nothing in flight to spare
  int slot = newest_slot_;
  const int older = (slot + kHealthSlots - 1) % kHealthSlots;
  if (!health_slots_[slot].fence.signalled() && !health_slots_[older].fence.empty()) slot = older;
  health_slots_[slot].fence.wait();
  HealthSnapshot snapshot;
  std::memcpy(&snapshot, static_cast<const std::byte*>(health_ring_.mapped()) + slot * sizeof(HealthSnapshot),
              sizeof snapshot);
  if (pair_control_.id() != 0) {
    pair_entries_ = snapshot.pairs.total;
    growPairList(snapshot.pairs);
  }
  Health out;
  out.flags = snapshot.health.flags;
  out.first_point = snapshot.health.flags != 0 ? (long long)snapshot.health.first_point : -1;
  out.substeps = health_slots_[slot].substeps;
  return out;
}

void GpuSolver::finish() {
  gl::finish();
}

void GpuSolver::clearHealth() {
  const gpu::Health clean{0u, 0xffffffffu, 0u, 0u};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  health_.upload(0, sizeof clean, &clean);
  health_checked_ = false;  // the next health() checks the current state again
  forgetSnapshots();        // their flags were raised before this
}

long long GpuSolver::deviceMemoryBytes() const {
  std::size_t total = 0;
  for (const StateBuffers& s : state_)
    total += s.position.size() + s.displacement.size();
  for (const gl::Buffer* b : {&xpbd_lambda_,
                              &coloured_points_,
                              &vbd_inertia_,
                              &health_ring_,
                              &params_,
                              &point_mass_,
                              &offsets_,
                              &neighbors_,
                              &colliders_,
                              &health_,
                              &grid_points_,
                              &grid_counts_,
                              &grid_start_,
                              &grid_blocks_,
                              &grid_scatter_,
                              &grid_sorted_,
                              &pair_control_,
                              &pair_anchor_,
                              &pair_start_,
                              &pair_list_,
                              &normals_,
                              &tangents_,
                              &vertex_tri_offsets_,
                              &vertex_tris_,
                              &triangles_,
                              &uvs_,
                              &pick_,
                              &coloured_springs_,
                              &colour_partners_,
                              &tethers_})
    total += b->size();
  return (long long)total;
}

}  // namespace drape
