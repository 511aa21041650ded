// Long-range attachments (core/tethers.hpp): which pins each point is tied to and at what rest distance,
// what the pass does to a state, and that they hold a fine hanging cloth that one XPBD sweep per substep
// lets stretch. CPU only; tests/gpu_tethers_gl_test.cpp holds the GPU to the same.
#include "core/tethers.hpp"
#include "core/metrics.hpp"
#include "cpu/cpu_solver.hpp"
#include "mesh_test_support.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

namespace drape {
namespace {

Scene standardScene(const std::string& name) {
  return loadScene(std::string(drape::test::sourceDir()) + "/scenes/" + name);
}

std::vector<std::uint32_t> pinsOf(const Topology& t) {
  std::vector<std::uint32_t> pins;
  for (std::size_t i = 0; i < t.pinned.size(); ++i)
    if (t.pinned[i]) pins.push_back(std::uint32_t(i));
  return pins;
}

// With at most kMaxTethers pins, every free point is tied to every pin, nearest first, at the straight
// distance of the flat rest shape; pins themselves are tied to nothing.
TEST(Tethers, AGridWithFewPinsTiesEveryFreePointToEveryPinAtItsRestDistance) {
  for (const char* name : {"pinned2.json", "pinned4.json"}) {
    SCOPED_TRACE(name);
    const Topology t = buildTopology(standardScene(name).cloth);
    const std::vector<std::uint32_t> pins = pinsOf(t);
    const Tethers tethers = buildTethers(t);
    ASSERT_EQ(tethers.slots, int(pins.size()));
    const std::size_t slots = std::size_t(tethers.slots);
    for (std::size_t i = 0; i < t.pinned.size(); ++i) {
      const std::uint32_t* anchor = &tethers.anchor[i * slots];
      const double* rest = &tethers.rest[i * slots];
      if (t.pinned[i]) {
        ASSERT_TRUE(std::all_of(anchor, anchor + slots, [](std::uint32_t a) { return a == kNoAnchor; })) << i;
        continue;
      }
      ASSERT_EQ(std::set<std::uint32_t>(anchor, anchor + slots), std::set<std::uint32_t>(pins.begin(), pins.end()))
          << "point " << i;
      for (std::size_t s = 0; s < slots; ++s) {
        ASSERT_EQ(rest[s], glm::distance(t.initial_positions[i], t.initial_positions[anchor[s]])) << i;
        if (s > 0) {
          ASSERT_LE(rest[s - 1], rest[s]) << "point " << i << ": nearest first";
        }
      }
    }
  }
}

// A whole pinned row: more pins than slots. Straight below a pin, that pin is the nearest along the
// springs (one step sideways costs a diagonal), so it is the first anchor.
TEST(Tethers, UnderAPinnedRowThePinAboveComesFirst) {
  Scene scene = standardScene("pinned2.json");
  scene.cloth.num_width_points = scene.cloth.num_height_points = 12;
  scene.cloth.pinned.clear();
  for (int x = 0; x < 12; ++x)
    scene.cloth.pinned.push_back({x, 0});
  const Topology t = buildTopology(scene.cloth);
  const Tethers tethers = buildTethers(t);
  ASSERT_EQ(tethers.slots, kMaxTethers);
  for (int y = 1; y < 12; ++y)
    for (int x = 0; x < 12; ++x) {
      const std::size_t i = std::size_t(y * 12 + x);
      EXPECT_EQ(tethers.anchor[i * kMaxTethers], std::uint32_t(x)) << x << "," << y;
      EXPECT_EQ(
          std::set<std::uint32_t>(&tethers.anchor[i * kMaxTethers], &tethers.anchor[(i + 1) * kMaxTethers]).size(),
          std::size_t(kMaxTethers))
          << "four different pins";
    }
}

// On a mesh the rest distance is a path along the sides and diagonals: never shorter than the straight
// distance in the rest shape (so the rest shape itself is never pulled), and on a folded sheet longer than
// it (so the sheet may unfold).
TEST(Tethers, AMeshsRestDistanceIsAPathAlongItsSides) {
  // A 6 x 6 quad grid folded at a right angle along its middle column: x = 0..0.5 flat, then up the wall.
  std::string obj;
  const int n = 6;
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      const double u = x / double(n - 1);
      obj += fmt::format("v {} {} {}\n", std::min(u, 0.6), 1.0 + std::max(u - 0.6, 0.0), z / double(n - 1));
    }
  for (int z = 0; z + 1 < n; ++z)
    for (int x = 0; x + 1 < n; ++x) {
      const int a = z * n + x + 1;
      obj += fmt::format("f {} {} {} {}\n", a, a + n, a + n + 1, a + 1);
    }
  mesh_test::writeFile("folded.obj", obj);
  const Scene scene = parseScene(R"({"cloth": {"mesh": "folded.obj", "thickness": 0.01, "pinned_vertices": [0]}})",
                                 (mesh_test::tempDir() / "scene.json").string());
  const Topology t = buildTopology(scene.cloth);
  const Tethers tethers = buildTethers(t);
  ASSERT_EQ(tethers.slots, 1);
  int longer = 0;
  for (std::size_t i = 1; i < t.pinned.size(); ++i) {
    ASSERT_EQ(tethers.anchor[i], 0u);
    const double straight = glm::distance(t.initial_positions[i], t.initial_positions[0]);
    EXPECT_GE(tethers.rest[i], straight * (1 - 1e-12)) << i;
    longer += tethers.rest[i] > straight * 1.01;
  }
  EXPECT_GT(longer, n) << "the points up the wall are further along the cloth than straight through the fold";
}

TEST(Tethers, TheyAreAPassOnlyWhenAskedForAndThereArePins) {
  Scene pinned2 = standardScene("pinned2.json");
  EXPECT_EQ(CpuSolver<float>(pinned2).passes(), (std::vector<std::string>{"forces", "integrate", "limit_stretch"}));
  pinned2.sim.tethers = true;
  EXPECT_EQ(CpuSolver<float>(pinned2).passes(),
            (std::vector<std::string>{"forces", "integrate", kTetherPassName, "limit_stretch"}));
  Scene sphere = standardScene("sphere.json");  // no pins: nothing to tie to
  sphere.sim.tethers = true;
  const std::vector<std::string> passes = CpuSolver<float>(sphere).passes();
  EXPECT_EQ(std::count(passes.begin(), passes.end(), kTetherPassName), 0);
  // Switched on live, they are built then.
  pinned2.sim.tethers = false;
  CpuSolver<float> live(pinned2);
  EXPECT_EQ(live.tethers().slots, 0);
  SimParams sim = pinned2.sim;
  sim.tethers = true;
  live.setParams(pinned2.cloth, sim);
  EXPECT_EQ(live.tethers().slots, 2);
  EXPECT_EQ(live.passes().at(2), kTetherPassName);
}

// One pin: after the pass no point is further from it than the limit, a point that was within it is not
// touched, and the displacement takes the same correction (x_prev stays).
TEST(Tethers, ThePassBringsEveryPointWithinTheLimitOfItsPinAndTouchesNoOther) {
  Scene scene = standardScene("pinned2.json");
  scene.cloth.num_width_points = scene.cloth.num_height_points = 16;
  scene.cloth.pinned = {{0, 0}};
  scene.sim.tethers = true;
  CpuSolver<double> solver(scene);
  const Topology& t = solver.topology();
  const glm::dvec3 pin = t.initial_positions[0];
  // Stretched away from the pin by 0 to 40%, depending on the point.
  std::vector<glm::dvec3> x(t.initial_positions.size()), v(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double stretch = 1.0 + 0.4 * double(i % 7) / 6.0;
    x[i] = pin + stretch * (t.initial_positions[i] - pin);
    v[i] = glm::dvec3(0.001 * double(i % 3), 0, 0);
  }
  solver.setState(x, v);
  solver.tether();
  const auto after = solver.readPositions();
  const auto disp = solver.readDisplacements();
  const double limit = scene.sim.stretch_limit;
  int moved = 0;
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double rest = glm::distance(t.initial_positions[i], pin);
    EXPECT_LE(glm::distance(after[i], pin), limit * rest * (1 + 1e-12)) << i;
    const bool within = glm::distance(x[i], pin) <= limit * rest;
    if (within) {
      EXPECT_EQ(after[i], x[i]) << i;
    } else {
      ++moved;
      EXPECT_NEAR(glm::distance(after[i], pin), limit * rest, 1e-12) << i;
    }
    EXPECT_LT(glm::length((disp[i] - v[i]) - (after[i] - x[i])), 1e-15) << i;
  }
  EXPECT_EQ(after[0], x[0]) << "the pin stays";
  EXPECT_GT(moved, int(x.size()) / 3);
}

// What they are for: pinned2 resampled to 96 x 96 (same ks per spring, so the corner springs carry more
// strain as the cloth gets finer) under XPBD with one sweep at 30 substeps. The springs carry the load one
// neighbour per sweep, so the finer the cloth, the more of the fall the springs at the pins take: measured
// 25% strain after 30 frames without tethers (2.4x at 256 x 256, and a blow-up from 512 x 512), and 10.4%
// with them, the stretch limit's 10% plus what one stretch pass leaves.
TEST(Tethers, HoldAFineClothThatOneXpbdSweepLetsStretch) {
  Scene scene = standardScene("pinned2.json");
  scene.cloth.num_width_points = scene.cloth.num_height_points = 96;
  scene.cloth.pinned = {{0, 0}, {95, 0}};
  scene.sim.self_collision = false;
  scene.sim.integrator = Integrator::Xpbd;
  double strain[2] = {0, 0};
  for (bool tethers : {false, true}) {
    scene.sim.tethers = tethers;
    CpuSolver<float> solver(scene);
    for (int f = 0; f < 30; ++f)
      solver.stepFrame();
    strain[tethers] = maxStrain(solver.topology(), scene.cloth, solver.readPositions());
    std::printf("96 x 96 pinned2, xpbd, tethers %s: max strain %.4f after 30 frames\n", tethers ? "on" : "off",
                strain[tethers]);
  }
  EXPECT_GT(strain[0], 0.2);
  EXPECT_LT(strain[1], 0.11);
}

}  // namespace
}  // namespace drape
