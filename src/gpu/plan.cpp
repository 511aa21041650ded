#include "gpu/plan.hpp"

#include "core/derived.hpp"
#include "gpu/kernels.hpp"
#include "gpu/layout.hpp"

#include <algorithm>

namespace drape::gpu {

namespace {

Dispatch dispatchOf(Pass pass, Stage stage, Extent extent, bool ping_pong) {
  Dispatch d;
  d.pass = pass;
  d.stage = stage;
  d.extent = extent;
  d.ping_pong = ping_pong;
  return d;
}

Dispatch indirect(Pass pass, std::uint32_t command) {
  Dispatch d = dispatchOf(pass, Stage::SelfCollide, Extent::Indirect, false);
  d.command = command;
  return d;
}

Dispatch tiles(Pass pass, Stage stage, std::uint32_t tile) {
  Dispatch d = dispatchOf(pass, stage, Extent::Tiles, true);
  d.tile = tile;
  return d;
}

// One dispatch per colour of `start` (colour c is [start[c], start[c + 1])), each in place over its range.
void addColours(std::vector<Dispatch>& out, Pass pass, Stage stage, const std::vector<std::uint32_t>& start,
                std::uint32_t sweep, bool skip_empty) {
  for (std::size_t c = 0; c + 1 < start.size(); ++c) {
    const std::uint32_t count = start[c + 1] - start[c];
    if (skip_empty && count == 0) continue;
    Dispatch d = dispatchOf(pass, stage, Extent::Range, false);
    d.first = start[c];
    d.count = count;
    d.sweep = sweep;
    out.push_back(d);
  }
}

// The candidate lists are rebuilt on the GPU's own decision (pairs_prepare writes the build's indirect dispatch
// sizes), so no read-back stalls the substep; when the lists are fresh, the build's dispatches run zero work
// groups.
void addListBuild(std::vector<Dispatch>& out, const ListLayout& lists) {
  Dispatch prepare = dispatchOf(Pass::PairsPrepare, Stage::SelfCollide, Extent::One, false);
  prepare.writes_commands = true;
  out.push_back(prepare);
  out.push_back(indirect(Pass::PairsGridCount, kPairDispatchPoints));
  if (lists.scan_blocks == 1) {
    out.push_back(indirect(Pass::GridBuild, kPairDispatchOne));
  } else {
    out.push_back(indirect(Pass::GridScan, kPairDispatchGridBlocks));
    out.push_back(indirect(Pass::GridScanBlocks, kPairDispatchOne));
    out.push_back(indirect(Pass::GridScanOffsets, kPairDispatchGridBlocks));
    out.push_back(indirect(Pass::GridScatter, kPairDispatchPoints));
    out.push_back(indirect(Pass::GridRank, kPairDispatchPoints));
  }
  out.push_back(indirect(Pass::PairsCount, kPairDispatchPoints));
  if (lists.point_scan_blocks == 1) {
    out.push_back(indirect(Pass::PairsScan, kPairDispatchOne));
  } else {
    out.push_back(indirect(Pass::PairsScan, kPairDispatchPointBlocks));
    out.push_back(indirect(Pass::PairsScanBlocks, kPairDispatchOne));
    out.push_back(indirect(Pass::PairsScanOffsets, kPairDispatchPointBlocks));
  }
  out.push_back(indirect(Pass::PairsFill, kPairDispatchPoints));
}

// The general and tiled paths' substep (docs/design.md section 4, the table of passes).
std::vector<Dispatch> substepOf(const Plan& p, const ClothCounts& counts) {
  const SceneNeeds& n = p.needs;
  std::vector<Dispatch> out;
  Dispatch integrate = p.path.tiled_forces
                           ? tiles(Pass::ForcesIntegrateTiled, Stage::Integrate, p.path.tiling.forces_tile)
                           : dispatchOf(Pass::ForcesIntegrate, Stage::Integrate, Extent::Points, true);
  integrate.checks_travel = n.fusion.travel_in_integrate;
  out.push_back(integrate);
  // In place, as the Gauss-Seidel stretch pass below (CpuSolver::solveXpbd, solveVbd).
  for (int sweep = 0; n.predicts && sweep < n.sweeps; ++sweep) {
    if (n.integrator == Integrator::Xpbd)
      addColours(out, Pass::XpbdColoured, Stage::Xpbd, counts.colour_start, std::uint32_t(sweep), true);
    else
      addColours(out, Pass::VbdColoured, Stage::Vbd, counts.point_colour_start, std::uint32_t(sweep), false);
  }
  if (n.fusion.collide_pass) out.push_back(dispatchOf(Pass::Collide, Stage::Collide, Extent::Points, true));
  if (n.contacts) {
    if (n.fusion.travel_pass) out.push_back(dispatchOf(Pass::PairsCheck, Stage::SelfCollide, Extent::Points, false));
    addListBuild(out, p.lists);
    out.push_back(dispatchOf(Pass::SelfCollide, Stage::SelfCollide, Extent::Points, true));
  }
  // In place: a point writes only itself and reads only anchors, which are pinned.
  if (p.tether_slots > 0) out.push_back(dispatchOf(Pass::Tether, Stage::Tether, Extent::Points, false));
  if (p.path.path == GpuPath::Tiled) {  // every colour of every pass in the one dispatch, blocks in shared memory
    if (n.stretch_passes > 0) out.push_back(tiles(Pass::LimitStretchTiled, Stage::Stretch, p.path.tiling.tile));
  } else {
    for (int pass = 0; pass < n.stretch_passes; ++pass) {
      if (!n.gauss_seidel) {
        out.push_back(dispatchOf(Pass::LimitStretch, Stage::Stretch, Extent::Points, true));
        continue;
      }
      // In place on the current state: the springs of one colour share no point, and the storage barrier
      // after each dispatch lets the next colour see the moved points (CpuSolver::limitStretchColoured).
      addColours(out, Pass::LimitStretchColoured, Stage::Stretch, counts.colour_start, 0, true);
    }
  }
  // The collisions have the last word (CpuSolver's collide_last): after the face contacts in their kernel, else
  // a pass of their own.
  if (n.faces) out.push_back(dispatchOf(Pass::CollideFaces, Stage::Faces, Extent::Points, true));
  if (n.fusion.collide_last_pass) out.push_back(dispatchOf(Pass::Collide, Stage::CollideLast, Extent::Points, true));
  out.back().advances = 1;
  return out;
}

Dispatch healthCheck() {
  return dispatchOf(Pass::Health, Stage::Health, Extent::Points, false);
}

Dispatch oneGroup(std::uint32_t substeps, std::uint32_t phases, bool check_health) {
  Dispatch d = dispatchOf(Pass::OneGroup, Stage::Integrate, Extent::One, false);
  d.substeps = substeps;
  d.phases = phases;
  d.check_health = check_health;
  return d;
}

// The one-dispatch path: a frame is one dispatch of every substep; the phases of a substep are listed as the
// general path's passes whose bodies they run.
void planOneGroup(Plan& p) {
  const SceneNeeds& n = p.needs;
  const std::uint32_t spf = std::uint32_t(n.steps_per_frame);
  p.substep = {oneGroup(1, kPhaseAll, false)};
  p.substep.back().advances = 1;
  p.frame.substep = {oneGroup(spf, kPhaseAll, true)};
  p.frame.substep.back().advances = int(spf);
  p.frame.repeats = 1;
  const std::string in = "in-group ";
  p.group_phases.push_back({kPhaseIntegrate, in + integrateLabel(n.fusion, false)});
  if (n.contacts) p.group_phases.push_back({kPhaseSelfCollide, in + passLabel(p, Pass::SelfCollide)});
  if (p.tether_slots > 0) p.group_phases.push_back({kPhaseTether, in + passLabel(p, Pass::Tether)});
  const Pass stretch = n.gauss_seidel ? Pass::LimitStretchColoured : Pass::LimitStretch;
  for (int pass = 0; pass < n.stretch_passes; ++pass)
    for (int c = 0; c < (n.gauss_seidel ? p.colours : 1); ++c)
      p.group_phases.push_back({kPhaseStretch, in + passLabel(p, stretch)});
  if (n.fusion.collide_last) p.group_phases.push_back({kPhaseCollideLast, in + passLabel(p, Pass::Collide)});
}

}  // namespace

ListLayout listLayout(std::uint64_t points, std::uint32_t buckets) {
  ListLayout l;
  l.buckets = buckets ? buckets : std::uint32_t(derived::hashBucketCount(points));
  l.scan_blocks = (l.buckets + kScanBlock - 1) / kScanBlock;
  l.point_scan_blocks = std::uint32_t((points + kScanBlock - 1) / kScanBlock);
  return l;
}

glm::uvec3 groupsFor(std::uint64_t invocations, std::uint32_t max_groups_x) {
  const std::uint64_t groups = std::max<std::uint64_t>((invocations + kLocalSize - 1) / kLocalSize, 1);
  if (groups <= max_groups_x) return {std::uint32_t(groups), 1, 1};
  const std::uint64_t rows = (groups + max_groups_x - 1) / max_groups_x;
  return {max_groups_x, std::uint32_t(rows), 1};
}

Plan makePlan(const PlanInput& in) {
  Plan p;
  p.needs = sceneNeeds(in.scene);
  p.tether_slots = p.needs.tethers ? in.counts.tether_slots : 0;
  decideFromCloth(p.needs, p.tether_slots > 0, in.counts.face_meshes > 0, in.counts.held_pairs);
  p.path = choosePath(p.needs, in.topo, in.colouring, p.tether_slots > 0, in.path, in.device);
  p.points = in.topo.pointCount();
  p.width = in.topo.W;
  p.height = in.topo.H;
  p.lists = listLayout(std::uint64_t(p.points), in.buckets);
  p.colours = in.colouring.colourCount();
  p.terms_held = in.terms_held;
  p.dt = in.scene.sim.dt();
  if (p.path.path == GpuPath::OneDispatch) {
    planOneGroup(p);
    return p;
  }
  p.substep = substepOf(p, in.counts);
  // The fused frame cuts the substeps' passes differently, in their own order: each substep's stretch limit
  // with the next one's forces (limit_stretch_forces_tiled.comp), then the last one's stretch limit.
  if (p.path.fused_frame) {
    Dispatch fused = tiles(Pass::LimitStretchForcesTiled, Stage::Integrate, p.path.tiling.fused_tile);
    fused.stretch_first = false;  // the frame's first substep has no stretch limit before it
    fused.advances = 1;
    Dispatch last = p.substep.back();  // limit_stretch_tiled
    last.advances = 0;
    p.frame.substep = {fused};
    p.frame.tail = {last};
  } else {
    p.frame.substep = p.substep;
  }
  p.frame.repeats = p.needs.steps_per_frame;
  p.frame.tail.push_back(healthCheck());
  if (p.needs.fusion.travel_in_integrate)
    p.travel_check = {dispatchOf(Pass::PairsCheck, Stage::SelfCollide, Extent::Points, false)};
  return p;
}

std::vector<Dispatch> stageDispatches(const Plan& plan, Stage stage, bool travel_checked) {
  if (stage == Stage::Health) return {healthCheck()};
  if (plan.path.path == GpuPath::OneDispatch) {
    const std::uint32_t phase = stage == Stage::Integrate     ? kPhaseIntegrate
                                : stage == Stage::SelfCollide ? kPhaseSelfCollide
                                : stage == Stage::Tether      ? kPhaseTether
                                : stage == Stage::Stretch     ? kPhaseStretch
                                : stage == Stage::CollideLast ? kPhaseCollideLast
                                                              : 0;
    if (phase == 0) return {};  // XPBD, VBD and their collide pass, the face contacts: the general path only
    if (phase == kPhaseCollideLast && !plan.needs.fusion.collide_last) return {};
    return {oneGroup(1, phase, false)};
  }
  std::vector<Dispatch> out;
  if (stage == Stage::SelfCollide && !travel_checked) out = plan.travel_check;
  for (const Dispatch& d : plan.substep)
    if (d.stage == stage) out.push_back(d);
  for (Dispatch& d : out)
    d.advances = 0;
  return out;
}

std::vector<std::string> substepListing(const Plan& plan) {
  std::vector<std::string> out;
  if (plan.path.path == GpuPath::OneDispatch) {
    for (const GroupPhase& phase : plan.group_phases)
      out.push_back(phase.name);
    return out;
  }
  for (const Dispatch& d : plan.frame.substep)
    out.push_back(passLabel(plan, d.pass));
  return out;
}

std::vector<std::string> frameListing(const Plan& plan) {
  std::vector<std::string> out;
  for (const Dispatch& d : plan.frame.tail)
    out.push_back(passLabel(plan, d.pass));
  return out;
}

int dispatchesPerFrame(const Plan& plan) {
  return int(plan.frame.substep.size()) * plan.frame.repeats + int(plan.frame.tail.size());
}

// The frame's health check is not a substep's.
double dispatchesPerSubstep(const Plan& plan) {
  double tail = 0;
  for (const Dispatch& d : plan.frame.tail)
    tail += d.stage == Stage::Health ? 0 : 1;
  return (double(plan.frame.substep.size()) * double(plan.frame.repeats) + tail) / double(plan.needs.steps_per_frame);
}

}  // namespace drape::gpu
