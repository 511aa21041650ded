// `drape bench --roofline`'s model and table on made-up runs and ceilings (no probing, no timing): the work
// counted per pass, which ceiling binds, and the share of it a pass reaches.
#include "app/roofline.hpp"
#include "cpu/machine_peak.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

namespace drape {
namespace {

BenchRun gridRun(int n, const std::string& kernels) {
  BenchRun run;
  run.scene = "scenes/pinned2.json";
  run.solver = "cpu";
  run.integrator = "verlet";
  run.threads = 1;
  run.team_threads = 1;
  run.size = n;
  run.points = (long long)n * n;
  run.grid_kernels = kernels;
  run.pair_entries_per_point = 3.5;
  run.planes = 1;
  return run;
}

// One thread's ceilings, made up: memory, L3 and L2 GB/s, add+mul GFLOP/s, div+sqrt G/s
MachinePeak peakOf(double dram, double l3, double l2, double addmul, double divsqrt) {
  MachinePeak p;
  p.isa = "avx2";
  p.threads = 1;
  p.dram_gbs = dram;
  p.l3_gbs = l3;
  p.cache_gbs = l2;
  p.addmul_gflops = addmul;
  p.divsqrt_gops = divsqrt;
  return p;
}

TEST(Roofline, AnInteriorPointHasTwelveSpringEnds) {
  // 2 ends a spring; a large grid's springs a point tend to 6, each with a square root and a division (once,
  // for both ends), so forces' count tends to 12.
  const std::optional<PassWork> w = passWork(gridRun(2048, "avx2"), "forces");
  ASSERT_TRUE(w);
  EXPECT_NEAR(w->divsqrt, 12, 0.05);
  EXPECT_NEAR(w->addmul, 14 * 12 + 3, 0.5);
  // On a small grid the border points have fewer springs.
  EXPECT_LT(passWork(gridRun(8, "avx2"), "forces")->divsqrt, 11);
}

// Where the grid path keeps the points in its arrays through the substeps, integrate runs in the forces' sweep:
// forces carries its work and no row of its own, and the stretch limit copies nothing in or back.
TEST(Roofline, IntegrateInTheForcesSweepIsCountedThere) {
  BenchRun kept = gridRun(256, "avx2");
  kept.points_in_arrays = true;
  const BenchRun copied = gridRun(256, "avx2");
  EXPECT_DOUBLE_EQ(passWork(kept, "forces")->addmul,
                   passWork(copied, "forces")->addmul + passWork(copied, "integrate")->addmul);
  EXPECT_DOUBLE_EQ(passWork(kept, "forces")->divsqrt, passWork(copied, "forces")->divsqrt);
  EXPECT_FALSE(passWork(kept, "integrate"));
  EXPECT_DOUBLE_EQ(passWork(copied, "limit_stretch")->bytes - passWork(kept, "limit_stretch")->bytes, 48);
}

TEST(Roofline, OnlyPassesTheModelCoversHaveWork) {
  EXPECT_FALSE(passWork(gridRun(50, ""), "forces")) << "the mesh path's gathers are not modelled";
  EXPECT_FALSE(passWork(gridRun(50, ""), "limit_stretch"));
  EXPECT_TRUE(passWork(gridRun(50, ""), "integrate")) << "integrate needs no grid";
  BenchRun other = gridRun(50, "avx2");
  other.integrator = "implicit-euler";
  EXPECT_FALSE(passWork(other, "integrate")) << "an integrator the model does not know";
  BenchRun cpu64 = gridRun(50, "avx2");
  cpu64.solver = "cpu64";
  EXPECT_FALSE(passWork(cpu64, "forces"));
  EXPECT_FALSE(passWork(gridRun(50, "avx2"), "tether"));
  // Self-collision's work grows with the list: 8 flops and 4 bytes an entry.
  BenchRun longer = gridRun(50, "avx2");
  longer.pair_entries_per_point = 13.5;
  EXPECT_DOUBLE_EQ(passWork(longer, "self_collide")->addmul - passWork(gridRun(50, "avx2"), "self_collide")->addmul,
                   80);
  EXPECT_DOUBLE_EQ(passWork(longer, "self_collide")->bytes - passWork(gridRun(50, "avx2"), "self_collide")->bytes, 40);
}

// XPBD: the prediction's forces are gravity alone, the integration is Verlet's, and its single sweep on the grid
// is a square root and two divisions a spring (6 springs a point inside a large grid); more sweeps, the mesh
// path and the stretch limit (which XPBD does not run) are not modelled.
TEST(Roofline, XpbdsSweepIsASquareRootAndTwoDivisionsASpring) {
  BenchRun xpbd = gridRun(2048, "avx2");
  xpbd.integrator = "xpbd";
  EXPECT_DOUBLE_EQ(passWork(xpbd, "forces")->divsqrt, 0);
  EXPECT_DOUBLE_EQ(passWork(xpbd, "forces")->addmul, 3);
  EXPECT_DOUBLE_EQ(passWork(xpbd, "integrate")->addmul, passWork(gridRun(2048, "avx2"), "integrate")->addmul);
  const std::optional<PassWork> sweep = passWork(xpbd, "xpbd_solve");
  ASSERT_TRUE(sweep);
  EXPECT_NEAR(sweep->divsqrt, 18, 0.05);
  EXPECT_NEAR(sweep->addmul, 34 * 6, 0.5);
  EXPECT_FALSE(passWork(xpbd, "limit_stretch"));
  EXPECT_FALSE(passWork(gridRun(2048, "avx2"), "xpbd_solve")) << "Verlet has no sweep";
  BenchRun mesh = xpbd;
  mesh.grid_kernels = "";
  EXPECT_FALSE(passWork(mesh, "xpbd_solve"));
  BenchRun three = xpbd;
  three.iterations = 3;
  EXPECT_FALSE(passWork(three, "xpbd_solve"));
}

// VBD: the prediction's forces are gravity alone, as XPBD's; a sweep is a square root and three divisions a
// spring end and seven divisions a point (the 3 x 3 solve), each later sweep all of it again; the mesh path's
// sweep and the stretch limit are not modelled.
TEST(Roofline, VbdsSweepIsFourRootsAndDivisionsASpringEndAndSevenAPoint) {
  BenchRun vbd = gridRun(2048, "avx2");
  vbd.integrator = "vbd";
  EXPECT_DOUBLE_EQ(passWork(vbd, "forces")->addmul, 3);
  EXPECT_DOUBLE_EQ(passWork(vbd, "integrate")->addmul, passWork(gridRun(2048, "avx2"), "integrate")->addmul);
  const std::optional<PassWork> one = passWork(vbd, "vbd_solve");
  ASSERT_TRUE(one);
  EXPECT_NEAR(one->divsqrt, 4 * 12 + 7, 0.2);
  EXPECT_NEAR(one->addmul, 38 * 12 + 27, 0.5);
  BenchRun three = vbd;
  three.iterations = 3;
  const std::optional<PassWork> more = passWork(three, "vbd_solve");
  ASSERT_TRUE(more);
  EXPECT_DOUBLE_EQ(more->divsqrt, 3 * one->divsqrt);
  EXPECT_DOUBLE_EQ(more->addmul, 3 * one->addmul + 2 * 6);
  EXPECT_DOUBLE_EQ(more->bytes, one->bytes + 36);
  EXPECT_FALSE(passWork(vbd, "limit_stretch"));
  EXPECT_FALSE(passWork(vbd, "xpbd_solve"));
  EXPECT_FALSE(passWork(gridRun(2048, "avx2"), "vbd_solve")) << "Verlet has no sweep";
  BenchRun mesh = vbd;
  mesh.grid_kernels = "";
  EXPECT_FALSE(passWork(mesh, "vbd_solve"));
}

TEST(Roofline, ShareIsTheLeastTimeOverTheMeasuredOne) {
  BenchReport r;
  r.machine.load_average = "0.50 0.40 0.30";
  r.peaks.push_back(peakOf(10, 0, 100, 20, 1));
  BenchRun small = gridRun(50, "avx2");  // 2500 points: its state fits L2
  const double calls = 30;               // a frame's substeps
  // integrate: 65 bytes, 15 add/mul. L2: 0.65 ns, add+mul: 0.75 ns, which binds. Measured 3 ns a point.
  small.passes.push_back({"integrate", 3e-6 * 2500 * calls, calls});
  // forces: 2 div+sqrt an end at 1 G/s is far over the rest.
  small.passes.push_back({"forces", 100e-6 * 2500 * calls, calls});
  BenchRun large = gridRun(512, "avx2");  // 262144 points: memory
  // integrate from memory: 65 bytes at 10 GB/s, 6.5 ns. 26 ns of wall clock with a core half the time is
  // 13 ns on it: half the roofline.
  large.passes.push_back({"integrate", 26e-6 * 512.0 * 512.0 * calls, calls});
  large.cpu_share = 0.5;
  r.runs = {small, large};
  const std::string md = rooflineMarkdown(r);
  EXPECT_NE(md.find("| 1 | 10.0 | 0.0 | 100.0 | 20.0 | 1.00 | – |"), std::string::npos) << md;
  EXPECT_NE(md.find("| pinned2 | 50 | cpu ×1 avx2 | integrate | 15 | 0 | 65 | 0.75 (add+mul) | 3.00 | 25% |"),
            std::string::npos)
      << md;
  const double forces_least = passWork(small, "forces")->divsqrt / 1.0;
  EXPECT_NE(md.find(fmt::format("| {:.2f} (div+sqrt) | 100.00 | {:.0f}% |", forces_least, forces_least)),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find(
          "| pinned2 | 512 | cpu ×1 avx2 (50% on a core) | integrate | 15 | 0 | 65 | 6.50 (memory) | 13.00 | 50% |"),
      std::string::npos)
      << md;
  EXPECT_EQ(rooflineMarkdown(BenchReport{}), "") << "no probes, no section";
}

// A cloth's state (128 bytes a point) past half a core's L2 but within the L3 probe's arrays and half the reported
// L3 is held to the L3's bandwidth; with no L3 reported, or past the probe's arrays, to memory's.
TEST(Roofline, AStateTheL3HoldsIsHeldToTheL3sBandwidth) {
  BenchReport r;
  MachinePeak one = peakOf(10, 40, 100, 1000, 1000);
  one.l2_bytes = 2 << 20;
  one.l3_bytes = 64 << 20;
  r.peaks.push_back(one);
  const double calls = 30;
  BenchRun mid = gridRun(256, "avx2");  // 8 MiB of state
  mid.passes.push_back({"integrate", 10e-6 * 256.0 * 256.0 * calls, calls});
  BenchRun large = gridRun(512, "avx2");  // 32 MiB: past the probe's 12 MiB
  large.passes.push_back({"integrate", 10e-6 * 512.0 * 512.0 * calls, calls});
  BenchRun small = gridRun(64, "avx2");  // 512 KiB: within half the 2 MiB L2
  small.passes.push_back({"integrate", 10e-6 * 64.0 * 64.0 * calls, calls});
  r.runs = {mid, large, small};
  std::string md = rooflineMarkdown(r);
  // integrate's 65 bytes at 40, 10 and 100 GB/s
  EXPECT_NE(md.find("| pinned2 | 256 | cpu ×1 avx2 | integrate | 15 | 0 | 65 | 1.62 (L3) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| pinned2 | 512 | cpu ×1 avx2 | integrate | 15 | 0 | 65 | 6.50 (memory) |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| pinned2 | 64 | cpu ×1 avx2 | integrate | 15 | 0 | 65 | 0.65 (L2) |"), std::string::npos) << md;
  r.peaks[0].l3_bytes = 0;  // the system does not say
  md = rooflineMarkdown(r);
  EXPECT_NE(md.find("| pinned2 | 256 | cpu ×1 avx2 | integrate | 15 | 0 | 65 | 6.50 (memory) |"), std::string::npos)
      << md;
}

TEST(Roofline, ATeamIsHeldToTheCeilingsOfItsThreads) {
  BenchReport r;
  MachinePeak one, two;
  one.threads = 1;
  two.threads = 2;
  one.dram_gbs = one.cache_gbs = one.addmul_gflops = one.divsqrt_gops = 1;
  two.dram_gbs = two.addmul_gflops = two.divsqrt_gops = 2;
  two.cache_gbs = 100;
  two.barrier_us = 3;
  two.barrier_best_us = 0.25;
  two.omp_barrier_us = 0.5;
  two.gap_share = 0.0264;
  two.gaps_per_second = 4512.4;
  two.long_gaps_per_second = 351.6;
  r.peaks = {one, two};
  BenchRun team = gridRun(50, "avx2");
  team.threads = team.team_threads = 2;
  team.cpu_share = 0.3;                                   // a team's waits for a core are its own cost: not taken out
  team.passes.push_back({"integrate", 15e-6 * 2500, 1});  // 15 flops at 2 GFLOP/s: 7.5 ns of 15 (one thread's
  // ceilings would allow 65 ns, more than was measured)
  r.runs = {team};
  const std::string md = rooflineMarkdown(r);
  EXPECT_NE(md.find("| 2 | 2.0 | 0.0 | 100.0 | 2.0 | 2.00 | 3.00, 0.25; 0.50 | 2.6%; 4512, 352 |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| 1 | 1.0 | 0.0 | 1.0 | 1.0 | 1.00 | – | 0.0%; 0, 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 7.50 (add+mul) | 15.00 | 50% |"), std::string::npos) << md;
}

// The time-taken probe's count: steps under 1 µs are the clock's own reads; the rest are gaps, lost whole.
TEST(Roofline, AGapIsAStepOfAMicrosecondOrMore) {
  using std::chrono::nanoseconds;
  GapCount c;
  for (const long long step : {40, 999, 1000, 15999, 16000, 250000, 30})
    c.add(nanoseconds(step));
  EXPECT_EQ(c.gaps, 4);
  EXPECT_EQ(c.long_gaps, 2);
  EXPECT_EQ(c.lost, nanoseconds(1000 + 15999 + 16000 + 250000));
}

}  // namespace
}  // namespace drape
