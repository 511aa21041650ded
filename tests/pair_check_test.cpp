// The self-collision lists' check on a grid cloth (CollisionPairs::startCheck and finishCheck): its first test, the
// box of every displacement (GridKernels::displacementBox), against the scalar box it stands for on every instruction
// set this CPU has, and the check with it against the check by tiles alone, on one thread and on a team whose threads
// box their own rows.
#include "cpu/aligned.hpp"
#include "cpu/collision_pairs.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/parallel.hpp"
#include "kernel_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace drape {
namespace {

using vec3 = glm::vec3;

using test::kernelSets;

// A grid's points in a GridPath's padded layout (cpu/grid_kernels.hpp), one array a coordinate
struct Padded {
  GridShape shape;
  PaddedFloats c[3];
  Padded(int w, int h) : shape(GridShape::of(w, h)) {
    for (PaddedFloats& a : c)
      a.assign(shape.size, 0.0f);
  }
  void set(const std::vector<vec3>& x) {
    for (int v = 0; v < shape.H; ++v)
      for (int u = 0; u < shape.W; ++u)
        for (int k = 0; k < 3; ++k)
          c[k][std::size_t(shape.at(u, v))] = x[std::size_t(v * shape.W + u)][k];
  }
};

// Rows [y0, y1) of widths that end a vector exactly (16, 32), a lane after (17, 33), and in between (37, 50): the
// least and greatest displacement of their points, lane for lane those of a loop over them; a NaN or an infinite
// displacement answers false.
TEST(PairCheck, TheDisplacementBoxIsTheLeastAndGreatestOfItsRows) {
  for (const int w : {16, 17, 32, 33, 37, 50}) {
    const int h = 9;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
    std::vector<vec3> x(std::size_t(w * h)), anchor(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      x[i] = vec3(coordinate(rng), coordinate(rng), coordinate(rng));
      // Every displacement positive: a padding lane's 0 would show as the least
      anchor[i] = x[i] - vec3(0.5f) + vec3(coordinate(rng), coordinate(rng), coordinate(rng)) * 0.01f;
    }
    Padded px(w, h), pa(w, h);
    px.set(x);
    pa.set(anchor);
    TileBoxArgs args{};
    args.shape = px.shape;
    args.px = px.c[0].data();
    args.py = px.c[1].data();
    args.pz = px.c[2].data();
    args.ax = pa.c[0].data();
    args.ay = pa.c[1].data();
    args.az = pa.c[2].data();
    for (const GridKernels* kern : kernelSets())
      for (const auto& [y0, y1] : {std::pair{0, h}, std::pair{0, 4}, std::pair{4, h}, std::pair{3, 4}}) {
        SCOPED_TRACE(::testing::Message() << kern->name << ", " << w << " wide, rows " << y0 << " to " << y1);
        float box[6];
        ASSERT_TRUE(kern->displacementBox(args, y0, y1, box));
        float expect[6] = {};
        for (int k = 0; k < 3; ++k) {
          expect[k] = std::numeric_limits<float>::infinity();
          expect[3 + k] = -std::numeric_limits<float>::infinity();
        }
        for (int v = y0; v < y1; ++v)
          for (int u = 0; u < w; ++u)
            for (int k = 0; k < 3; ++k) {
              const std::size_t i = std::size_t(v * w + u);
              expect[k] = std::min(expect[k], x[i][k] - anchor[i][k]);
              expect[3 + k] = std::max(expect[3 + k], x[i][k] - anchor[i][k]);
            }
        for (int k = 0; k < 6; ++k)
          EXPECT_EQ(box[k], expect[k]) << "number " << k;
        // The row's last point, whose lane may share a vector with the padding
        const std::size_t last = std::size_t(px.shape.at(w - 1, y1 - 1));
        for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
          const float kept = px.c[1][last];
          px.c[1][last] = bad;
          EXPECT_FALSE(kern->displacementBox(args, y0, y1, box)) << bad;
          px.c[1][last] = kept;
        }
      }
  }
}

// A 40 x 64 cloth (5 x 8 tiles of 8 points: a team splits the check) with CS184's 50 x 50 proportions (contact
// distance 0.95 of the spacing: too few stencil offsets for its squares, so the box of every displacement is tested
// first) under a fold that sweeps across, the rows past a moving line lifting, its second half sliding, and a jitter:
// the check that tests that box first answers as the one by tiles alone at every step, on one thread and on a team of
// two whose threads box their own rows; the box alone clears most checks, not all; a NaN calls for a build.
TEST(PairCheck, TheBoxOfEveryDisplacementAnswersAsTheTilesDo) {
  const float spacing = 0.02f, range = 0.019f, margin = 0.75f * range;
  const int n = 40, h = 64;
  std::vector<vec3> rest;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < n; ++u)
      rest.push_back(vec3(float(u) * spacing, 0.0f, float(v) * spacing));
  CollisionPairs<float> tiles, whole, team;
  for (CollisionPairs<float>* p : {&tiles, &whole, &team}) {
    p->configure(range, margin);
    p->setRest(rest);
    p->setGrid(n, h);
    p->setKernels(&gridKernels(GridIsa::Auto));
  }
  Padded padded(n, h);
  const auto give = [&](CollisionPairs<float>& p) {
    p.setPaddedPositions(&padded.shape, padded.c[0].data(), padded.c[1].data(), padded.c[2].data());
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> jitter(-0.0003f, 0.0003f);
  std::vector<vec3> x = rest;
  int builds = 0;
  const auto step = [&](long long s) {
    padded.set(x);
    give(tiles);
    const bool a = tiles.update(x, 1);  // startCheck without a stamp: by tiles alone
    give(whole);
    whole.startCheck(x, s);
    const bool b = whole.finishCheck(x);
    if (b) whole.build(x, 1);
    bool c = false;
    runOnTeam(2, [&] {
      long long y0, y1;
      teamShare(0, h, y0, y1);
      team.boxDisplacements(teamThread(), s, padded.shape, padded.c[0].data(), padded.c[1].data(), padded.c[2].data(),
                            int(y0), int(y1));
      teamSingle([&] {
        give(team);
        team.startCheck(x, s);
      });
      const bool mine = team.finishCheck(x);
      if (mine) team.build(x, 1);
      if (teamThread() == 0) c = mine;
    });
    EXPECT_EQ(b, a) << "step " << s;
    EXPECT_EQ(c, a) << "step " << s;
    builds += a;
  };
  long long s = 0;
  for (; s < 400; ++s) {
    const int line = int(s / 10) % n;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < n; ++u) {
        vec3& p = x[std::size_t(v * n + u)];
        p += vec3(jitter(rng), jitter(rng), jitter(rng));
        if (u > line) p.y += 0.0006f;
        if (v >= h / 2) p.z += 0.0002f;  // the second thread's rows slide against the first's
      }
    step(s);
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(builds, 20);
  EXPECT_LT(builds, 300);
  for (const CollisionPairs<float>* p : {&whole, &team}) {
    EXPECT_EQ(p->rebuilds(), tiles.rebuilds());
    EXPECT_EQ(p->closerLooksKept(), tiles.closerLooksKept());
    EXPECT_GT(p->checksClearedWhole(), 100) << "the box of every displacement cleared few checks";
    EXPECT_LT(p->checksClearedWhole(), 400 - builds) << "every check was cleared by the box alone";
  }
  EXPECT_EQ(tiles.checksClearedWhole(), 0);
  // One point's displacement not finite: every check calls for a build
  step(s++);
  x[std::size_t(n * h / 2)].y = std::numeric_limits<float>::quiet_NaN();
  const int before = builds;
  step(s++);
  EXPECT_EQ(builds, before + 1);
}

}  // namespace
}  // namespace drape
