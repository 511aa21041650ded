// The GPU solver's plan without a GL context (src/gpu/plan.hpp): what a substep and a frame dispatch for each
// scene, path and device, the fusion rule, the stage functions' dispatches, the kernel table and the traffic
// model. tests/gpu_solver_gl_test.cpp holds the dispatches a real solver issues against the same plan.
#include "core/colouring.hpp"
#include "core/tethers.hpp"
#include "gpu/cloth_tables.hpp"
#include "gpu/face_tables.hpp"
#include "gpu/kernels.hpp"
#include "gpu/layout.hpp"
#include "gpu/plan.hpp"
#include "gpu/traffic.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace drape {
namespace {

using gpu::Dispatch;
using gpu::Pass;
using gpu::Plan;
using Strings = std::vector<std::string>;

// Loaded once each: a scene with mesh obstacles bakes their distance fields on load.
Scene bundled(const std::string& file) {
  static std::map<std::string, Scene> loaded;
  auto it = loaded.find(file);
  if (it == loaded.end())
    it = loaded.emplace(file, loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + file)).first;
  return it->second;
}

// What llvmpipe reports (Mesa 22.3): the device every pinned figure below was taken on.
gpu::DeviceLimits llvmpipe() {
  gpu::DeviceLimits d;
  d.shared_bytes = 32768;
  d.group_invocations = d.group_size_x = 1024;
  d.max_groups_x = d.max_groups_y = 65535;
  d.max_buffer_bytes = 134217728;
  d.storage_bindings = 80;
  d.software = true;
  return d;
}

// NVIDIA's GL on a hardware GPU: 48 KiB of shared memory; the automatic choice is not the general path there.
gpu::DeviceLimits nvidia() {
  gpu::DeviceLimits d = llvmpipe();
  d.shared_bytes = 49152;
  d.software = false;
  return d;
}

// A scene's cloth as the solver holds it, and the plan for it.
struct Planned {
  Scene scene;
  Topology topo;
  SpringColouring colouring;
  gpu::ClothCounts counts;
  Plan plan;

  Planned(Scene s, GpuPath path, const gpu::DeviceLimits& device) : scene(std::move(s)) {
    topo = buildTopology(scene.cloth);
    colouring = colourSprings(topo);
    const gpu::SceneNeeds needs = gpu::sceneNeeds(scene);
    counts.colour_start = gpu::colouredSprings(topo, colouring, needs).start;
    counts.adjacency_entries = gpu::adjacency(topo, needs).neighbors.size();
    if (scene.sim.integrator == Integrator::Vbd) counts.point_colour_start = colourPoints(topo).start;
    if (scene.sim.tethers) counts.tether_slots = buildTethers(topo).slots;
    counts.face_meshes = gpu::faceTables(scene, topo).meshes;
    counts.held_pairs = scene.sim.self_collision && gpu::mayHoldPairs(topo, 2.0 * scene.cloth.thickness);
    plan = gpu::makePlan({scene, topo, colouring, counts, path, device, 0, 0});
  }

  double bytes(double candidates = 0) const {
    const double n = double(topo.pointCount());
    return gpu::bytesPerPointPerSubstep(plan, {n, double(counts.adjacency_entries) / n, candidates});
  }
};

Strings labels(const Plan& plan, const std::vector<Dispatch>& dispatches) {
  Strings out;
  for (const Dispatch& d : dispatches)
    out.push_back(gpu::passLabel(plan, d.pass));
  return out;
}

constexpr int kRefused = -1;

struct Pinned {
  const char* scene;
  GpuPath path;
  Integrator integrator;
  int dispatches_per_frame;  // kRefused: a forced path that does not fit
  double bytes;              // the traffic model, a point and substep
};

// Every bundled scene on every forced path with every integrator (its own iterations), on llvmpipe: the
// dispatches a frame and the traffic model's bytes a point and substep as GpuSolver reported them at 38264b2,
// before the plan was a value of its own. The restructuring changed neither; a deliberate change of the plan or
// the model changes this table with it: issue 26 added the collisions again after the stretch limit (a collide
// dispatch a substep where a scene has colliders) and the face contacts (the mesh scenes with sharp features,
// which no longer fit the one-dispatch path).
// clang-format off
const Pinned kPinned[] = {
    {"flag.json", GpuPath::General, Integrator::Verlet, 421, 1789.2718894009217},
    {"flag.json", GpuPath::Tiled, Integrator::Verlet, kRefused, 0},
    {"flag.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"flag.json", GpuPath::General, Integrator::Xpbd, 811, 3083.9815668202759},
    {"flag.json", GpuPath::Tiled, Integrator::Xpbd, kRefused, 0},
    {"flag.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"flag.json", GpuPath::General, Integrator::Vbd, 571, 2226.7096774193546},
    {"flag.json", GpuPath::Tiled, Integrator::Vbd, kRefused, 0},
    {"flag.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"mannequin.json", GpuPath::General, Integrator::Verlet, 631, 1856.6836734693875},
    {"mannequin.json", GpuPath::Tiled, Integrator::Verlet, 301, 895.83673469387759},
    {"mannequin.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"mannequin.json", GpuPath::General, Integrator::Xpbd, 1021, 3160.8265306122448},
    {"mannequin.json", GpuPath::Tiled, Integrator::Xpbd, 691, 2485.0714285714284},
    {"mannequin.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"mannequin.json", GpuPath::General, Integrator::Vbd, 871, 2204.1428571428569},
    {"mannequin.json", GpuPath::Tiled, Integrator::Vbd, 541, 1528.3877551020407},
    {"mannequin.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"pinned2.json", GpuPath::General, Integrator::Verlet, 391, 1084.9408000000003},
    {"pinned2.json", GpuPath::Tiled, Integrator::Verlet, 32, 77.425066666666666},
    {"pinned2.json", GpuPath::OneDispatch, Integrator::Verlet, 1, 2.3999999999999999},
    {"pinned2.json", GpuPath::General, Integrator::Xpbd, 751, 2384.3200000000002},
    {"pinned2.json", GpuPath::Tiled, Integrator::Xpbd, 421, 1713.1775999999998},
    {"pinned2.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"pinned2.json", GpuPath::General, Integrator::Vbd, 601, 1431.3792000000003},
    {"pinned2.json", GpuPath::Tiled, Integrator::Vbd, 271, 760.23680000000002},
    {"pinned2.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"pinned4.json", GpuPath::General, Integrator::Verlet, 391, 1084.9408000000003},
    {"pinned4.json", GpuPath::Tiled, Integrator::Verlet, 32, 77.425066666666666},
    {"pinned4.json", GpuPath::OneDispatch, Integrator::Verlet, 1, 2.3999999999999999},
    {"pinned4.json", GpuPath::General, Integrator::Xpbd, 751, 2384.3200000000002},
    {"pinned4.json", GpuPath::Tiled, Integrator::Xpbd, 421, 1713.1775999999998},
    {"pinned4.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"pinned4.json", GpuPath::General, Integrator::Vbd, 601, 1431.3792000000003},
    {"pinned4.json", GpuPath::Tiled, Integrator::Vbd, 271, 760.23680000000002},
    {"pinned4.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"plane.json", GpuPath::General, Integrator::Verlet, 631, 1204.9408000000003},
    {"plane.json", GpuPath::Tiled, Integrator::Verlet, 301, 250.0224},
    {"plane.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"plane.json", GpuPath::General, Integrator::Xpbd, 1021, 2504.3200000000002},
    {"plane.json", GpuPath::Tiled, Integrator::Xpbd, 691, 1833.1775999999998},
    {"plane.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"plane.json", GpuPath::General, Integrator::Vbd, 871, 1551.3792000000003},
    {"plane.json", GpuPath::Tiled, Integrator::Vbd, 541, 880.23680000000002},
    {"plane.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"selfCollision.json", GpuPath::General, Integrator::Verlet, 631, 1204.9408000000003},
    {"selfCollision.json", GpuPath::Tiled, Integrator::Verlet, 301, 721.95839999999998},
    {"selfCollision.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"selfCollision.json", GpuPath::General, Integrator::Xpbd, 1021, 2504.3200000000002},
    {"selfCollision.json", GpuPath::Tiled, Integrator::Xpbd, 691, 2021.3375999999998},
    {"selfCollision.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"selfCollision.json", GpuPath::General, Integrator::Vbd, 871, 1551.3792000000003},
    {"selfCollision.json", GpuPath::Tiled, Integrator::Vbd, 541, 1068.3968},
    {"selfCollision.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"sphere.json", GpuPath::General, Integrator::Verlet, 631, 1204.9408000000003},
    {"sphere.json", GpuPath::Tiled, Integrator::Verlet, 301, 250.0224},
    {"sphere.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"sphere.json", GpuPath::General, Integrator::Xpbd, 1021, 2504.3200000000002},
    {"sphere.json", GpuPath::Tiled, Integrator::Xpbd, 691, 1833.1775999999998},
    {"sphere.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"sphere.json", GpuPath::General, Integrator::Vbd, 871, 1551.3792000000003},
    {"sphere.json", GpuPath::Tiled, Integrator::Vbd, 541, 880.23680000000002},
    {"sphere.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"tablecloth.json", GpuPath::General, Integrator::Verlet, 631, 1855.1222222222223},
    {"tablecloth.json", GpuPath::Tiled, Integrator::Verlet, 301, 895.28888888888889},
    {"tablecloth.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"tablecloth.json", GpuPath::General, Integrator::Xpbd, 1021, 3157.2777777777774},
    {"tablecloth.json", GpuPath::Tiled, Integrator::Xpbd, 691, 2483.4111111111115},
    {"tablecloth.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"tablecloth.json", GpuPath::General, Integrator::Vbd, 871, 2202.155555555556},
    {"tablecloth.json", GpuPath::Tiled, Integrator::Vbd, 541, 1528.2888888888888},
    {"tablecloth.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"torus.json", GpuPath::General, Integrator::Verlet, 631, 1203.4861111111111},
    {"torus.json", GpuPath::Tiled, Integrator::Verlet, 301, 248.11111111111111},
    {"torus.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"torus.json", GpuPath::General, Integrator::Xpbd, 1021, 2501.0138888888887},
    {"torus.json", GpuPath::Tiled, Integrator::Xpbd, 691, 1831.6805555555557},
    {"torus.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"torus.json", GpuPath::General, Integrator::Vbd, 871, 1549.5277777777783},
    {"torus.json", GpuPath::Tiled, Integrator::Vbd, 541, 880.19444444444434},
    {"torus.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"two_spheres.json", GpuPath::General, Integrator::Verlet, 631, 1204.9408000000003},
    {"two_spheres.json", GpuPath::Tiled, Integrator::Verlet, 301, 250.0224},
    {"two_spheres.json", GpuPath::OneDispatch, Integrator::Verlet, kRefused, 0},
    {"two_spheres.json", GpuPath::General, Integrator::Xpbd, 1021, 2504.3200000000002},
    {"two_spheres.json", GpuPath::Tiled, Integrator::Xpbd, 691, 1833.1775999999998},
    {"two_spheres.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"two_spheres.json", GpuPath::General, Integrator::Vbd, 871, 1551.3792000000003},
    {"two_spheres.json", GpuPath::Tiled, Integrator::Vbd, 541, 880.23680000000002},
    {"two_spheres.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
    {"wind.json", GpuPath::General, Integrator::Verlet, 391, 1132.9408000000003},
    {"wind.json", GpuPath::Tiled, Integrator::Verlet, 61, 649.95839999999998},
    {"wind.json", GpuPath::OneDispatch, Integrator::Verlet, 1, 247.21279999999999},
    {"wind.json", GpuPath::General, Integrator::Xpbd, 751, 2432.3200000000002},
    {"wind.json", GpuPath::Tiled, Integrator::Xpbd, 421, 1949.3375999999998},
    {"wind.json", GpuPath::OneDispatch, Integrator::Xpbd, kRefused, 0},
    {"wind.json", GpuPath::General, Integrator::Vbd, 601, 1479.3792000000003},
    {"wind.json", GpuPath::Tiled, Integrator::Vbd, 271, 996.39679999999998},
    {"wind.json", GpuPath::OneDispatch, Integrator::Vbd, kRefused, 0},
};
// clang-format on

TEST(GpuPlan, EveryBundledSceneKeepsItsDispatchesAndTraffic) {
  for (const Pinned& p : kPinned) {
    Scene scene = bundled(p.scene);
    scene.sim.integrator = p.integrator;
    const Planned planned(scene, p.path, llvmpipe());
    const Plan& plan = planned.plan;
    SCOPED_TRACE(std::string(p.scene) + " " + integratorName(p.integrator) + " path " + std::to_string(int(p.path)));
    if (p.dispatches_per_frame == kRefused) {
      EXPECT_NE(plan.path.refusal, "");
      EXPECT_EQ(plan.path.path, GpuPath::General) << "a refused path falls back to the general one on a live change";
      continue;
    }
    EXPECT_EQ(plan.path.refusal, "");
    EXPECT_EQ(plan.path.path, p.path);
    EXPECT_EQ(gpu::dispatchesPerFrame(plan), p.dispatches_per_frame);
    EXPECT_EQ(planned.bytes(), p.bytes);
    // On llvmpipe the automatic choice is the general path.
    if (p.path == GpuPath::General) {
      const Planned automatic(scene, GpuPath::Auto, llvmpipe());
      EXPECT_EQ(labels(automatic.plan, automatic.plan.frame.substep), labels(plan, plan.frame.substep));
    }
  }
}

// Collisions run once, in the kernel that moved the point last, and once more where a pass moves the points
// after them (in the face contacts' kernel where that runs); the lists' travel check once, where the positions
// are those self-collision will see.
TEST(GpuPlan, TheFusionRulePlacesCollisionsAndTheTravelCheckOnce) {
  for (const bool contacts : {false, true})
    for (const bool colliders : {false, true})
      for (const bool predicts : {false, true})
        for (const bool moved_after : {false, true})
          for (const bool faces : {false, true}) {
            if (faces && !(moved_after && colliders)) continue;  // the face contacts are a mesh's and move points
            const gpu::Fusion f = gpu::fusionRule(contacts, colliders, predicts, moved_after, faces);
            SCOPED_TRACE(std::to_string(contacts) + std::to_string(colliders) + std::to_string(predicts) +
                         std::to_string(moved_after) + std::to_string(faces));
            EXPECT_EQ(f.collide_last, colliders && moved_after);
            EXPECT_EQ(int(f.collide_in_faces) + int(f.collide_last_pass), f.collide_last ? 1 : 0);
            EXPECT_EQ(f.collide_in_faces, f.collide_last && faces) << "the face contacts move the point last";
            EXPECT_EQ(int(f.collide_in_integrate) + int(f.collide_in_contacts) + int(f.collide_pass),
                      colliders ? 1 : 0);
            EXPECT_EQ(int(f.travel_in_integrate) + int(f.travel_pass), contacts ? 1 : 0);
            EXPECT_EQ(f.collide_in_contacts, colliders && contacts) << "self-collision moves the point last";
            EXPECT_FALSE(predicts && (f.collide_in_integrate || f.travel_in_integrate)) << "the sweeps move it after";
          }
}

// The collisions have the last word (issue 26): after the stretch limit a collide pass, or the face contacts'
// kernel where a mesh has sharp features; neither where no pass moves the points after the collisions, nor
// without colliders; and the face contacts only where their tables have a mesh.
TEST(GpuPlan, TheCollisionsRunAgainAfterThePassesThatMovePointsAndOnlyThere) {
  const auto last = [](const Planned& p) { return gpu::substepListing(p.plan).back(); };
  const auto count = [](const Planned& p, const std::string& label) {
    const Strings l = gpu::substepListing(p.plan);
    return std::count(l.begin(), l.end(), label);
  };
  const Planned sphere(bundled("sphere.json"), GpuPath::General, llvmpipe());
  EXPECT_EQ(last(sphere), "collide");
  EXPECT_EQ(count(sphere, "collide_faces+collide"), 0);
  const Planned drop(bundled("box_drop.json"), GpuPath::General, llvmpipe());
  EXPECT_EQ(drop.counts.face_meshes, 1);
  EXPECT_EQ(last(drop), "collide_faces+collide");
  EXPECT_EQ(count(drop, "collide"), 0) << "the face contacts' kernel collides again";
  const Planned pinned(bundled("pinned2.json"), GpuPath::General, llvmpipe());
  EXPECT_EQ(count(pinned, "collide"), 0) << "no colliders";
  Scene unlimited = bundled("sphere.json");
  unlimited.sim.stretch_passes = 0;
  EXPECT_EQ(count(Planned(unlimited, GpuPath::General, llvmpipe()), "collide"), 0) << "nothing moves them after";
  Scene small = bundled("sphere.json");
  small.sim.self_collision = false;
  const Planned one(small, GpuPath::OneDispatch, llvmpipe());
  ASSERT_EQ(one.plan.path.path, GpuPath::OneDispatch) << one.plan.path.one_dispatch_misfit;
  EXPECT_EQ(last(one), "in-group collide");
  EXPECT_FALSE(Planned(bundled("sphere.json"), GpuPath::Tiled, llvmpipe()).plan.path.fused_frame)
      << "the ring's points would need their displacements to collide";
}

// A frame on the general path: each substep's dispatches steps_per_frame times, then the health check; every
// enabled spring is in exactly one stretch dispatch a pass, and the wind's time moves on once a substep.
TEST(GpuPlan, AGeneralFrameIsItsSubstepsThenTheHealthCheck) {
  Scene scene = bundled("sphere.json");
  scene.sim.stretch_passes = 2;
  const Planned planned(scene, GpuPath::General, llvmpipe());
  const Plan& plan = planned.plan;
  EXPECT_EQ(labels(plan, plan.frame.substep), labels(plan, plan.substep));
  EXPECT_EQ(plan.frame.repeats, scene.sim.steps_per_frame);
  EXPECT_EQ(labels(plan, plan.frame.tail), (Strings{"health"}));
  EXPECT_EQ(gpu::frameListing(plan), (Strings{"health"}));
  std::uint32_t stretched = 0;
  int advances = 0;
  for (const Dispatch& d : plan.substep) {
    if (d.pass == Pass::LimitStretchColoured) stretched += d.count;
    advances += d.advances;
  }
  EXPECT_EQ(stretched, 2 * planned.topo.springs.size()) << "two passes over every spring";
  EXPECT_EQ(advances, 1);
  EXPECT_EQ(plan.substep.back().advances, 1) << "after the substep's last dispatch";
  EXPECT_EQ(gpu::dispatchesPerFrame(plan), int(plan.substep.size()) * scene.sim.steps_per_frame + 1);
  EXPECT_DOUBLE_EQ(gpu::dispatchesPerSubstep(plan), double(plan.substep.size()));
  // selfCollision with the sphere's colliders: integrate checks the travel, self-collision collides.
  EXPECT_EQ(gpu::substepListing(plan).front(), "forces+integrate+pairs_check");
  const Strings listing = gpu::substepListing(plan);
  EXPECT_NE(std::find(listing.begin(), listing.end(), "self_collide+collide"), listing.end());
}

// The fused frame (tiled path, a flat grid without self-collision, tethers or wind): one dispatch a substep
// that stretches the previous substep's copy first, except in the frame's first, then the last stretch limit;
// step() alone ends on a whole substep with the two kernels.
TEST(GpuPlan, TheFusedFrameCutsTheSubstepsDifferently) {
  Scene scene;
  scene.cloth.num_width_points = scene.cloth.num_height_points = 256;
  scene.cloth.pinned = {{0, 0}, {255, 0}};
  scene.sim.self_collision = false;
  const Planned planned(scene, GpuPath::Tiled, llvmpipe());
  const Plan& plan = planned.plan;
  ASSERT_TRUE(plan.path.fused_frame);
  EXPECT_EQ(plan.path.tiling.halo, 10u) << "one pass over the grid colouring reaches 10 points";
  EXPECT_EQ(labels(plan, plan.substep), (Strings{"forces_tiled+integrate", "limit_stretch_tiled"}));
  ASSERT_EQ(plan.frame.substep.size(), 1u);
  EXPECT_EQ(plan.frame.substep[0].pass, Pass::LimitStretchForcesTiled);
  EXPECT_FALSE(plan.frame.substep[0].stretch_first) << "nothing to stretch before the frame's first forces";
  EXPECT_EQ(plan.frame.substep[0].tile, plan.path.tiling.fused_tile);
  EXPECT_EQ(labels(plan, plan.frame.tail), (Strings{"limit_stretch_tiled", "health"}));
  EXPECT_EQ(plan.frame.tail[0].advances, 0) << "the last stretch limit ends the last substep, already counted";
  EXPECT_EQ(gpu::dispatchesPerFrame(plan), scene.sim.steps_per_frame + 2);
  EXPECT_DOUBLE_EQ(gpu::dispatchesPerSubstep(plan), double(scene.sim.steps_per_frame + 1) / scene.sim.steps_per_frame);
  // Without the grid's one rest per direction (a vertical cloth's points are offset), nothing is fused.
  const Planned wind(bundled("wind.json"), GpuPath::Tiled, llvmpipe());
  EXPECT_TRUE(wind.plan.path.grid_rests.empty());
  EXPECT_TRUE(wind.plan.path.colour_partners) << "the tiled stretch limit reads the ColourPartner table";
  EXPECT_FALSE(wind.plan.path.fused_frame);
}

// The one-dispatch path: a frame is one dispatch of every substep and the health check; step() and the stage
// functions one substep of the phases they ask for.
TEST(GpuPlan, TheOneDispatchPathIsAPlanToo) {
  const Planned planned(bundled("pinned2.json"), GpuPath::OneDispatch, llvmpipe());
  const Plan& plan = planned.plan;
  const int substeps = planned.scene.sim.steps_per_frame;
  ASSERT_EQ(plan.path.path, GpuPath::OneDispatch);
  ASSERT_EQ(plan.frame.substep.size(), 1u);
  const Dispatch& frame = plan.frame.substep[0];
  EXPECT_EQ(frame.pass, Pass::OneGroup);
  EXPECT_EQ(frame.substeps, std::uint32_t(substeps));
  EXPECT_EQ(frame.phases, gpu::kPhaseAll);
  EXPECT_TRUE(frame.check_health);
  EXPECT_EQ(frame.advances, substeps);
  EXPECT_EQ(plan.frame.repeats, 1);
  EXPECT_TRUE(plan.frame.tail.empty());
  EXPECT_EQ(gpu::dispatchesPerFrame(plan), 1);
  EXPECT_DOUBLE_EQ(gpu::dispatchesPerSubstep(plan), 1.0 / substeps);
  const Strings listing = gpu::substepListing(plan);
  ASSERT_EQ(listing.size(), 13u);
  EXPECT_EQ(listing[0], "in-group forces+integrate");
  EXPECT_EQ(Strings(listing.begin() + 1, listing.end()), Strings(12, "in-group limit_stretch_colour"));
  EXPECT_FALSE(plan.path.grid_rests.empty()) << "a flat grid: the springs from the grid";
  const std::pair<gpu::Stage, std::uint32_t> stages[] = {{gpu::Stage::Integrate, gpu::kPhaseIntegrate},
                                                         {gpu::Stage::SelfCollide, gpu::kPhaseSelfCollide},
                                                         {gpu::Stage::Tether, gpu::kPhaseTether},
                                                         {gpu::Stage::Stretch, gpu::kPhaseStretch}};
  for (const auto& [stage, phase] : stages) {
    const std::vector<Dispatch> run = gpu::stageDispatches(plan, stage, false);
    ASSERT_EQ(run.size(), 1u);
    EXPECT_EQ(run[0].phases, phase);
    EXPECT_EQ(run[0].substeps, 1u);
    EXPECT_EQ(run[0].advances, 0) << "a stage is no whole substep";
  }
  EXPECT_TRUE(gpu::stageDispatches(plan, gpu::Stage::Xpbd, false).empty());
  // The general path's collisions and self-collision phases, named as its passes.
  Scene self = bundled("sphere.json");
  self.cloth.num_width_points = self.cloth.num_height_points = 32;
  const Planned contacts(self, GpuPath::OneDispatch, llvmpipe());
  EXPECT_EQ(gpu::substepListing(contacts.plan)[0], "in-group forces+integrate");
  EXPECT_EQ(gpu::substepListing(contacts.plan)[1], "in-group self_collide+collide");
}

// A stage function runs the stage's dispatches of the substep; self-collision on a state no forces+integrate
// checked starts with the lists' travel check, which a whole Verlet substep fuses into integrate.
TEST(GpuPlan, StagesRunTheirShareOfTheSubstep) {
  const Planned planned(bundled("selfCollision.json"), GpuPath::General, llvmpipe());
  const Plan& plan = planned.plan;
  const std::vector<Dispatch> unchecked = gpu::stageDispatches(plan, gpu::Stage::SelfCollide, false);
  const std::vector<Dispatch> checked = gpu::stageDispatches(plan, gpu::Stage::SelfCollide, true);
  ASSERT_EQ(unchecked.size(), checked.size() + 1);
  EXPECT_EQ(unchecked.front().pass, Pass::PairsCheck);
  EXPECT_EQ(checked.front().pass, Pass::PairsPrepare);
  EXPECT_EQ(checked.back().pass, Pass::SelfCollide);
  for (const Dispatch& d : plan.substep)
    EXPECT_NE(d.pass, Pass::PairsCheck) << "fused into forces+integrate";
  EXPECT_TRUE(plan.substep.front().checks_travel);
  // XPBD moves the points after the prediction: the check is a pass of the substep.
  Scene xpbd = bundled("selfCollision.json");
  xpbd.sim.integrator = Integrator::Xpbd;
  const Planned sweeps(xpbd, GpuPath::General, llvmpipe());
  EXPECT_FALSE(sweeps.plan.substep.front().checks_travel);
  const std::vector<Dispatch> self = gpu::stageDispatches(sweeps.plan, gpu::Stage::SelfCollide, false);
  EXPECT_EQ(self.front().pass, Pass::PairsCheck);
  EXPECT_EQ(self.size(), checked.size() + 1);
  const std::vector<Dispatch> health = gpu::stageDispatches(plan, gpu::Stage::Health, false);
  ASSERT_EQ(health.size(), 1u);
  EXPECT_EQ(health[0].pass, Pass::Health);
}

// A forced path that does not fit says why; the message is what the solver throws at construction.
TEST(GpuPlan, AForcedPathThatDoesNotFitSaysWhy) {
  EXPECT_EQ(Planned(bundled("flag.json"), GpuPath::Tiled, llvmpipe()).plan.path.refusal,
            "gpu solver: the tiled stretch limit does not apply: the tiled stretch limit needs a grid cloth (a mesh "
            "cloth's springs have no blocks)");
  Scene jacobi = bundled("pinned2.json");
  jacobi.sim.stretch_scheme = StretchScheme::Jacobi;
  EXPECT_NE(Planned(jacobi, GpuPath::Tiled, llvmpipe()).plan.path.refusal.find("Jacobi"), std::string::npos);
  const Planned general(bundled("flag.json"), GpuPath::General, llvmpipe());
  EXPECT_EQ(general.plan.path.tiled_misfit, "not asked for") << "the colouring's reach is not worked out";
  EXPECT_EQ(general.plan.path.one_dispatch_misfit,
            "the contacts with a mesh's sharp edges and corners run on the general path only (collide_faces.comp)")
      << "the flag's pole has sharp edges";
  EXPECT_EQ(Planned(bundled("pinned2.json"), GpuPath::General, llvmpipe()).plan.path.one_dispatch_misfit, "")
      << "pinned2 fits one work group";
  Scene vbd = bundled("pinned2.json");
  vbd.sim.integrator = Integrator::Vbd;
  EXPECT_EQ(Planned(vbd, GpuPath::OneDispatch, llvmpipe()).plan.path.refusal,
            "gpu solver: the one-dispatch path does not fit: the vbd integrator runs on the general path only "
            "(one_group.comp has Verlet's phases)");
  Scene many = bundled("pinned2.json");
  many.sim.stretch_passes = 4;  // reach 35 points on a 50x50 grid: 78 a side, over 48 KiB
  const std::string refusal = Planned(many, GpuPath::Tiled, nvidia()).plan.path.refusal;
  EXPECT_NE(refusal.find("4 stretch passes reach 35 points"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("(49152)"), std::string::npos) << refusal;
  EXPECT_EQ(Planned(many, GpuPath::Auto, nvidia()).plan.path.refusal, "") << "the automatic choice refuses nothing";
  // On a hardware GPU the automatic choice is the one-dispatch path where it fits, else the general one: the tiled
  // path, slower on an H200, only when asked for.
  EXPECT_EQ(Planned(bundled("pinned2.json"), GpuPath::Auto, nvidia()).plan.path.path, GpuPath::OneDispatch);
  Scene large = bundled("pinned2.json");
  large.cloth.num_width_points = large.cloth.num_height_points = 128;
  EXPECT_EQ(Planned(large, GpuPath::Auto, nvidia()).plan.path.path, GpuPath::General);
  EXPECT_EQ(Planned(large, GpuPath::Tiled, nvidia()).plan.path.path, GpuPath::Tiled);
}

// Every pass has its row: a kernel file that exists, a name, and defines without a name twice; every planned
// dispatch's bytes come from its row.
TEST(GpuKernels, EveryPassHasARowWithItsKernel) {
  const Planned planned(bundled("selfCollision.json"), GpuPath::General, llvmpipe());
  std::set<std::string> names;
  for (std::size_t p = 0; p < gpu::kPassCount; ++p) {
    const gpu::KernelRow& row = gpu::kernelRow(Pass(p));
    SCOPED_TRACE(row.name);
    EXPECT_EQ(row.pass, Pass(p));
    EXPECT_NE(row.defines, nullptr);
    EXPECT_NE(row.bytes, nullptr);
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(drape::test::sourceDir()) / "glsl" / row.file))
        << row.file;
    EXPECT_TRUE(names.insert(row.name).second) << "a name twice";
    for (int variant = 0; variant < row.variants; ++variant) {
      std::set<std::string> defined;
      for (const auto& [name, value] : gpu::kernelDefines(planned.plan, Pass(p), variant))
        EXPECT_TRUE(defined.insert(name).second) << name << " defined twice";
    }
  }
  // The integrate kernel sees where the plan put the collisions and the travel check.
  const gl::Defines integrate = gpu::kernelDefines(planned.plan, Pass::ForcesIntegrate);
  EXPECT_NE(std::find(integrate.begin(), integrate.end(), gl::Defines::value_type{"TRAVEL_CHECK", "1"}),
            integrate.end());
  EXPECT_NE(std::find(integrate.begin(), integrate.end(), gl::Defines::value_type{"COLLIDE_AFTER_INTEGRATE", "0"}),
            integrate.end());
  const gl::Defines contacts = gpu::kernelDefines(planned.plan, Pass::SelfCollide);
  EXPECT_NE(std::find(contacts.begin(), contacts.end(), gl::Defines::value_type{"COLLIDE_AFTER_CONTACTS", "1"}),
            contacts.end());
}

// The traffic model follows the plan: each Gauss-Seidel stretch pass adds its springs' bytes (the entry, both
// ends' state read and written: 16 + 4 x 28 per spring), self-collision the list's candidates (a 4-byte index
// and a 16-byte gather each).
TEST(GpuTraffic, TheModelIsLinearInTheStretchPassesAndTheCandidates) {
  Scene scene;
  scene.cloth.num_width_points = scene.cloth.num_height_points = 12;
  scene.sim.self_collision = false;
  const auto bytes = [&](int passes) {
    scene.sim.stretch_passes = passes;
    return Planned(scene, GpuPath::General, llvmpipe()).bytes();
  };
  const double none = bytes(0), one = bytes(1), two = bytes(2);
  const Topology topo = buildTopology(scene.cloth);
  constexpr double kState = sizeof(glm::vec4) + sizeof(glm::vec3);  // a position and a packed displacement
  const double per_pass = double(topo.springs.size()) * (sizeof(gpu::ColouredSpring) + 4 * kState) / topo.pointCount();
  EXPECT_GT(none, 0.0);
  EXPECT_DOUBLE_EQ(one - none, per_pass);
  EXPECT_DOUBLE_EQ(two - one, per_pass);
  scene.sim.stretch_passes = 1;
  scene.sim.self_collision = true;
  const Planned self(scene, GpuPath::General, llvmpipe());
  EXPECT_DOUBLE_EQ(self.bytes(3.0) - self.bytes(0.0), 3.0 * (4 + 16));
}

// The traffic model of the fused kernel, from the tiling a device's shared memory allows: with the 48 KiB
// that NVIDIA's drivers report, blocks of 39 with a ring of 12 copy about 2.4 positions a point at 256²
// and 1024², under the 100 bytes a point and substep issue #10 aims for; with llvmpipe's 32 KiB, blocks of
// 27 copy 3.4 and the model counts about 102.
TEST(GpuTiling, TheFusedKernelsTrafficFollowsTheSharedMemory) {
  const gpu::StretchTiling nvidia = gpu::tilingFor(49152, 1024, 10);
  EXPECT_EQ(nvidia.tile, 43u);
  EXPECT_EQ(nvidia.fused_tile, 39u);
  EXPECT_EQ(nvidia.group_size, 512u);
  const gpu::StretchTiling llvmpipe = gpu::tilingFor(32768, 1024, 10);
  EXPECT_EQ(llvmpipe.tile, 31u);
  EXPECT_EQ(llvmpipe.fused_tile, 27u);
  for (const int n : {256, 1024, 2048}) {
    SCOPED_TRACE(n);
    const double at48 = gpu::fusedBytesPerPoint(n, n, nvidia), at32 = gpu::fusedBytesPerPoint(n, n, llvmpipe);
    std::printf("fused kernel at %d²: %.1f bytes a point with 48 KiB, %.1f with 32 KiB\n", n, at48, at32);
    EXPECT_LE(at48, 100.0);
    EXPECT_LE(at32, 100.0) << "llvmpipe's 32 KiB: the 12-byte displacements keep it under";
    EXPECT_GT(at32, at48);
    // A 16-byte position (w: the pin flag) and a packed 12-byte displacement, read and written.
    EXPECT_GT(at48, 2 * (sizeof(glm::vec4) + sizeof(glm::vec3))) << "at least the position, displacement and new state";
  }
  // Copies of 31 a side: blocks of 11 for the stretch limit, too few inside the wider ring for the fused kernel.
  const gpu::StretchTiling small = gpu::tilingFor(12 * 31 * 31 + 4 * 31, 1024, 10);
  EXPECT_EQ(small.tile, 11u);
  EXPECT_EQ(small.fused_tile, 0u);
}

}  // namespace
}  // namespace drape
