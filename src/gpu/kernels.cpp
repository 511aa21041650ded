#include "gpu/kernels.hpp"

#include "core/tethers.hpp"

#include <array>

namespace drape::gpu {

namespace {

void number(gl::Defines& d, const char* name, std::uint64_t value) {
  d.emplace_back(name, std::to_string(value));
}

void flag(gl::Defines& d, const char* name, bool value) {
  d.emplace_back(name, value ? "1" : "0");
}

// Each kernel's defines, built here and nowhere else: the scene's, and what the plan chose for the kernel.
void scene(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
}

void integrate(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  flag(d, "COLLIDE_AFTER_INTEGRATE", p.needs.fusion.collide_in_integrate);
  flag(d, "TRAVEL_CHECK", p.needs.fusion.travel_in_integrate);
}

void integrateTiled(const Plan& p, int, gl::Defines& d) {
  integrate(p, 0, d);
  number(d, "GROUP_SIZE", p.path.tiling.forces_group_size);
  number(d, "TILE", p.path.tiling.forces_tile);
}

void contacts(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  number(d, "TERMS_HELD", std::uint64_t(p.terms_held));
  flag(d, "COLLIDE_AFTER_CONTACTS", p.needs.fusion.collide_in_contacts);
}

// SCAN_STAGE 0..2: the three dispatches of a scan beyond kScanBlock counts; 3: the whole scan in one.
void gridScan(int stage, const Plan& p, gl::Defines& d) {
  d = sceneDefines(p.needs);
  number(d, "SCAN_STAGE", std::uint64_t(stage));
}

void gridScan0(const Plan& p, int, gl::Defines& d) {
  gridScan(0, p, d);
}

void gridScan1(const Plan& p, int, gl::Defines& d) {
  gridScan(1, p, d);
}

void gridScan2(const Plan& p, int, gl::Defines& d) {
  gridScan(2, p, d);
}

void pairsScan(int stage, const Plan& p, gl::Defines& d) {
  gridScan(stage, p, d);
  d.emplace_back("PAIR_SCAN", "1");
}

void pairsScan0(const Plan& p, int, gl::Defines& d) {
  pairsScan(p.lists.point_scan_blocks == 1 ? 3 : 0, p, d);
}

void pairsScan1(const Plan& p, int, gl::Defines& d) {
  pairsScan(1, p, d);
}

void pairsScan2(const Plan& p, int, gl::Defines& d) {
  pairsScan(2, p, d);
}

void stretchTiled(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  number(d, "GROUP_SIZE", p.path.tiling.group_size);
  number(d, "TILE", p.path.tiling.tile);
  number(d, "HALO", p.path.tiling.halo);
  flag(d, "GRID_SPRINGS", !p.path.grid_rests.empty());
}

// The forces need a ring of 2 stretched points around a block, so the fused copy's ring is 2 wider.
void stretchForcesTiled(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  number(d, "GROUP_SIZE", p.path.tiling.group_size);
  number(d, "TILE", p.path.tiling.fused_tile);
  number(d, "HALO", p.path.tiling.halo + 2);
  flag(d, "COLLIDE_AFTER_INTEGRATE", p.needs.fusion.collide_in_integrate);
}

void faces(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  flag(d, "COLLIDE_AFTER_FACES", p.needs.fusion.collide_in_faces);
}

void oneGroup(const Plan& p, int, gl::Defines& d) {
  d = sceneDefines(p.needs);
  number(d, "GROUP_SIZE", p.path.group_size);
  number(d, "GROUP_POINTS", std::uint64_t(p.points));
  number(d, "GROUP_BUCKETS", p.path.group_buckets);
  if (p.tether_slots > 0) number(d, "TETHER_SLOTS", std::uint64_t(p.tether_slots));
  if (!p.path.grid_rests.empty()) d.emplace_back("GRID_SPRINGS", "1");
  flag(d, "COLLIDE_AFTER_INTEGRATE", p.needs.fusion.collide_in_integrate);
  flag(d, "COLLIDE_AFTER_CONTACTS", p.needs.fusion.collide_in_contacts);
  flag(d, "COLLIDE_LAST", p.needs.fusion.collide_last);
}

// Its code depends on nothing in the scene but the slots.
void tether(const Plan& p, int, gl::Defines& d) {
  number(d, "TETHER_SLOTS", std::uint64_t(p.tether_slots));
}

void pick(const Plan&, int stage, gl::Defines& d) {
  number(d, "PICK_STAGE", std::uint64_t(stage));
}

constexpr std::uint8_t kNoUniforms = 0;
constexpr std::uint16_t kNoBindings = 0;

// clang-format off
constexpr std::array<KernelRow, kPassCount> kRows = {{
  {Pass::ForcesIntegrate, "forces+integrate", "sim/forces_integrate.comp", Label::Integrate, integrate, kNoBindings, kUniformTime, Fixed::None, traffic::forces},
  {Pass::ForcesIntegrateTiled, "forces_tiled+integrate", "sim/forces_integrate_tiled.comp", Label::TiledIntegrate, integrateTiled, kNoBindings, kNoUniforms, Fixed::GridForces, traffic::forcesTiled},
  {Pass::PairsCheck, "pairs_check", "sim/pairs_check.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsPrepare, "pairs_prepare", "sim/pairs_prepare.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsGridCount, "pairs_grid_count", "sim/pairs_grid_count.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridBuild, "grid_build", "sim/grid_build.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridScan, "grid_scan", "sim/grid_scan.comp", Label::Plain, gridScan0, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridScanBlocks, "grid_scan_blocks", "sim/grid_scan.comp", Label::Plain, gridScan1, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridScanOffsets, "grid_scan_offsets", "sim/grid_scan.comp", Label::Plain, gridScan2, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridScatter, "grid_scatter", "sim/grid_scatter.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::GridRank, "grid_rank", "sim/grid_rank.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsCount, "pairs_count", "sim/pairs_count.comp", Label::Plain, scene, kBindRest, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsScan, "pairs_scan", "sim/grid_scan.comp", Label::Plain, pairsScan0, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsScanBlocks, "pairs_scan_blocks", "sim/grid_scan.comp", Label::Plain, pairsScan1, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsScanOffsets, "pairs_scan_offsets", "sim/grid_scan.comp", Label::Plain, pairsScan2, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
  {Pass::PairsFill, "pairs_fill", "sim/pairs_fill.comp", Label::Plain, scene, kBindRest, kNoUniforms, Fixed::None, traffic::none},
  {Pass::SelfCollide, "self_collide", "sim/self_collide.comp", Label::Contacts, contacts, kBindRest, kNoUniforms, Fixed::None, traffic::selfCollide},
  {Pass::LimitStretch, "limit_stretch", "sim/limit_stretch.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::stretchJacobi},
  {Pass::LimitStretchColoured, "limit_stretch_colour", "sim/limit_stretch_coloured.comp", Label::Plain, scene, kBindColouredSprings, kUniformRange, Fixed::None, traffic::stretchColour},
  {Pass::LimitStretchTiled, "limit_stretch_tiled", "sim/limit_stretch_tiled.comp", Label::Plain, stretchTiled, kBindColourPartners, kNoUniforms, Fixed::Stretch, traffic::stretchTiled},
  {Pass::LimitStretchForcesTiled, "limit_stretch_forces_tiled+integrate", "sim/limit_stretch_forces_tiled.comp", Label::FusedIntegrate, stretchForcesTiled, kNoBindings, kUniformStretchFirst, Fixed::Stretch, traffic::stretchForcesTiled},
  {Pass::OneGroup, "one_group", "sim/one_group.comp", Label::Plain, oneGroup, kBindColourPartners | kBindTethers, kUniformGroup, Fixed::Group, traffic::oneGroup},
  {Pass::XpbdColoured, "xpbd_colour", "sim/xpbd_coloured.comp", Label::Plain, scene, kBindColouredSprings | kBindXpbdLambda, kUniformRange | kUniformSweep, Fixed::None, traffic::xpbdColour},
  {Pass::VbdColoured, "vbd_colour", "sim/vbd_coloured.comp", Label::Plain, scene, kBindColouredPoints | kBindVbdInertia, kUniformRange | kUniformSweep, Fixed::None, traffic::vbdColour},
  {Pass::Collide, "collide", "sim/collide.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::collide},
  {Pass::Tether, kTetherPassName, "sim/tether.comp", Label::Plain, tether, kBindTethers, kNoUniforms, Fixed::None, traffic::tether},
  {Pass::CollideFaces, "collide_faces", "sim/collide_faces.comp", Label::Faces, faces, kBindFaces, kNoUniforms, Fixed::None, traffic::collideFaces},
  {Pass::Pick, "pick", "sim/pick.comp", Label::Plain, pick, kBindPick, kNoUniforms, Fixed::None, traffic::none, 2},
  {Pass::Health, "health", "sim/health.comp", Label::Plain, scene, kNoBindings, kNoUniforms, Fixed::None, traffic::none},
}};
// clang-format on

// A pass without its row, or a row out of place, does not compile: a row left out leaves the table's last one
// empty, whose pass is not the last Pass. (The function pointers are checked by tests/gpu_plan_test.cpp: the
// address of a function of another file is no constant to compare under the sanitizers.)
constexpr bool rowsInOrder() {
  for (std::size_t p = 0; p < kPassCount; ++p)
    if (kRows[p].pass != Pass(p) || kRows[p].name == nullptr || kRows[p].file == nullptr || kRows[p].variants < 1)
      return false;
  return true;
}
static_assert(rowsInOrder(), "the kernel table needs one complete row per Pass, in the enum's order");

}  // namespace

const KernelRow& kernelRow(Pass pass) {
  return kRows[std::size_t(pass)];
}

std::string integrateLabel(const Fusion& f, bool travel) {
  return std::string("forces+integrate") + (travel && f.travel_in_integrate ? "+pairs_check"
                                            : f.collide_in_integrate        ? "+collide"
                                                                            : "");
}

std::string passLabel(const Plan& plan, Pass pass) {
  const KernelRow& row = kernelRow(pass);
  const Fusion& f = plan.needs.fusion;
  switch (row.label) {
    case Label::Plain:
      return row.name;
    case Label::Integrate:
      return plan.needs.predicts ? "forces+predict" : integrateLabel(f, true);
    case Label::TiledIntegrate:
      return std::string(row.name) + (f.travel_in_integrate    ? "+pairs_check"
                                      : f.collide_in_integrate ? "+collide"
                                                               : "");
    case Label::Faces:
      return std::string(row.name) + (f.collide_in_faces ? "+collide" : "");
    case Label::Contacts:
    case Label::FusedIntegrate:
      return std::string(row.name) +
             ((row.label == Label::Contacts ? f.collide_in_contacts : f.collide_in_integrate) ? "+collide" : "");
  }
  return row.name;
}

gl::Defines kernelDefines(const Plan& plan, Pass pass, int variant) {
  gl::Defines d;
  kernelRow(pass).defines(plan, variant, d);
  return d;
}

gl::Defines sceneDefines(const SceneNeeds& n) {
  gl::Defines d = {{"NUM_SPHERES", std::to_string(n.spheres)},
                   {"NUM_PLANES", std::to_string(n.planes)},
                   {"SELF_COLLISION", n.contacts ? "1" : "0"},
                   {"WIND", n.wind ? "1" : "0"},
                   {"UNIFORM_MASS", n.grid ? "1" : "0"}};
  if (n.meshes > 0) d.emplace_back("NUM_MESHES", std::to_string(n.meshes));
  if (n.predicts) d.emplace_back("PREDICT", "1");
  if (n.held) d.emplace_back("HELD_AT_REST", "1");
  if (n.integrator == Integrator::Xpbd) d.emplace_back("XPBD_LAMBDA", n.sweep_state ? "1" : "0");
  if (n.integrator == Integrator::Vbd) d.emplace_back("VBD_INERTIA", n.sweep_state ? "1" : "0");
  return d;
}

}  // namespace drape::gpu
