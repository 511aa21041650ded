// The contact kernels against the scalar code they stand for: pairTerms against
// physics::selfCollisionCorrections and cellOrder, tilesMovedApart against CollisionPairs' tile comparison
// without kernels, on every instruction set this CPU has.
#include "cpu/collision_pairs.hpp"
#include "cpu/grid_kernels.hpp"
#include "cpu/physics.hpp"
#include "kernel_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace drape {
namespace {

using vec3 = glm::vec3;

using test::kernelSets;

// GCC 12 once put a zeroed pair of floats through an MMX register in the baseline pairTerms and left it
// there (no emms): every x87 register is then in MMX use, and long double arithmetic after it, strtold
// included, gives NaN. The kernels' units are built with -mno-mmx; this is what shows it.
bool x87Usable() {
  return std::strtold("0.5", nullptr) == 0.5L;
}

bool sameBits(vec3 a, const float b[3]) {
  return std::memcmp(&a.x, b, 3 * sizeof(float)) == 0;
}

// pairTerms' entries [0, a.size()) against physics::selfCollisionCorrections and cellOrder; returns the pairs in range
// and counts those whose distance is NaN and those whose cells are not neighbours.
int expectScalarTerms(const GridKernels& kern, const std::vector<vec3>& x, const std::vector<std::uint32_t>& a,
                      const std::vector<std::uint32_t>& b, float thickness, int& nans, int& far_cells) {
  const float inv_range = 1 / (2 * thickness);
  std::vector<PairTermOut> out(a.size());
  const int found = kern.pairTerms(&x.data()->x, x.size(), a.data(), b.data(), 0, std::uint32_t(a.size()), thickness,
                                   inv_range, out.data());
  int expected = 0;
  nans = far_cells = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const vec3 xi = x[a[k]], xj = x[b[k]];
    vec3 ci, cj;
    if (!physics::selfCollisionCorrections(xi, xj, thickness, ci, cj)) continue;
    if (expected >= found) {
      ADD_FAILURE() << "entry " << k << " in range is missing";
      return found;
    }
    const PairTermOut& o = out[std::size_t(expected++)];
    EXPECT_EQ(o.k, k);
    const vec3 d = xi - xj;
    if (!(glm::dot(d, d) == glm::dot(d, d))) {
      EXPECT_EQ(o.order_i, -2) << k;
      ++nans;
      continue;
    }
    EXPECT_TRUE(sameBits(ci, o.ci)) << k;
    EXPECT_TRUE(sameBits(cj, o.cj)) << k;
    const glm::ivec3 cell_i = HashGrid<float>::cellOf(xi, inv_range), cell_j = HashGrid<float>::cellOf(xj, inv_range);
    EXPECT_EQ(o.order_i, cellOrder(cell_i, cell_j)) << k;
    EXPECT_EQ(o.order_j, cellOrder(cell_j, cell_i)) << k;
    far_cells += o.order_i < 0;
  }
  EXPECT_EQ(found, expected);
  return expected;
}

// Pairs around the contact distance, and the cases the kernel must treat as the scalar code does: a point on
// itself (distance 0), a pair exactly at the range, equal coordinates (the sign of a zero term), cells far
// apart or beyond the clamp of HashGrid::cellOf, negative coordinates on cell boundaries, and NaN.
TEST(ContactKernels, PairTermsAreTheScalarTermsAndOrders) {
  const float thickness = 0.0095f, range = 2 * thickness;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-0.5f, 0.5f), offset(-1.2f * range, 1.2f * range);
  std::vector<vec3> x;
  std::vector<std::uint32_t> a, b;
  const auto add = [&](vec3 p, vec3 q) {
    a.push_back(std::uint32_t(x.size()));
    x.push_back(p);
    b.push_back(std::uint32_t(x.size()));
    x.push_back(q);
  };
  for (int k = 0; k < 3000; ++k) {
    const vec3 p(coord(rng), coord(rng), coord(rng));
    add(p, p + vec3(offset(rng), offset(rng), offset(rng)));
  }
  const float nan = std::numeric_limits<float>::quiet_NaN(), huge = 3e10f;
  add(vec3(0.1f), vec3(0.1f));                                               // distance 0
  add(vec3(0, 0, 0), vec3(range, 0, 0));                                     // exactly at the range
  add(vec3(0.25f, 0.5f, -0.75f), vec3(0.25f, 0.5f + 0.3f * range, -0.75f));  // equal x and z
  add(vec3(-range, -2 * range, 0), vec3(-range * 0.99f, -2 * range, 0.0f));  // on cell boundaries, negative
  add(vec3(huge, 0, 0), vec3(huge, range * 0.5f, 0));                        // beyond the cells' clamp
  add(vec3(-huge, 0, 0), vec3(-huge, 0, range * 0.5f));
  add(vec3(nan, 0, 0), vec3(0.0f));
  add(vec3(0.0f), vec3(0, nan, 0));
  for (const GridKernels* kern : kernelSets()) {
    SCOPED_TRACE(kern->name);
    int nans = 0, far_cells = 0;
    const int expected = expectScalarTerms(*kern, x, a, b, thickness, nans, far_cells);
    EXPECT_EQ(nans, 2);
    EXPECT_GT(expected, 500);  // the random pairs put a good share in range
    EXPECT_GT(expected - far_cells, 500);
    EXPECT_TRUE(x87Usable()) << "pairTerms left the x87 registers to MMX";
  }
}

// A list as the lists hold it: by owner, ascending, a few partners each, so that a vector's owners lie within a few
// points of its first (Avx512::loadVec3Near loads them whole where they lie within kNear and inside the array):
// spans of 9 and 10 points, a vector whose owners end at the array's last point, and the whole lanes' gather of the
// partners (gatherVec3Whole) with tails of every length.
TEST(ContactKernels, PairTermsOfAListByOwner) {
  const float thickness = 0.02f;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> coord(0.0f, 0.06f);
  std::vector<vec3> x(300);
  for (vec3& p : x)
    p = vec3(coord(rng), coord(rng), coord(rng));
  const auto n = std::uint32_t(x.size());
  std::vector<std::uint32_t> a, b;
  const auto entry = [&](std::uint32_t i, std::uint32_t j) {
    a.push_back(i);
    b.push_back(j);
  };
  for (std::uint32_t i = 0; i < n; ++i)
    for (auto e = std::uint32_t(rng() % 5); e > 0; --e)
      entry(i, std::uint32_t(rng() % n));
  for (const std::uint32_t span : {9u, 10u})  // sixteen entries from owner 100 to 100 + span
    for (std::uint32_t l = 0; l < 16; ++l)
      entry(100 + l * span / 15, std::uint32_t(rng() % n));
  for (std::uint32_t l = 0; l < 16; ++l)  // the last vector's owners end at the last point
    entry(n - 1 - (15 - l) / 4, std::uint32_t(rng() % n));
  for (const GridKernels* kern : kernelSets()) {
    SCOPED_TRACE(kern->name);
    for (std::size_t tail = 0; tail < 16; ++tail) {  // every count of lanes in the last vector
      const std::vector<std::uint32_t> a_part(a.begin(), a.end() - std::ptrdiff_t(tail)),
          b_part(b.begin(), b.end() - std::ptrdiff_t(tail));
      int nans = 0, far_cells = 0;
      EXPECT_GT(expectScalarTerms(*kern, x, a_part, b_part, thickness, nans, far_cells), 100);
      EXPECT_EQ(nans, 0);
    }
  }
}

// tileBoxes' twelve numbers a tile (the least and greatest displacement and position in x, y and z) are the minima and
// maxima over the tile's points, from vec3 arrays and from a grid path's padded ones, for squares as wide as a vector,
// narrower (a partial one), one lane wider and wider still; and a NaN displacement answers false.
TEST(ContactKernels, TileBoxesAreEachTilesLeastAndGreatest) {
  const int w = 53, h = 41;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
  std::vector<vec3> x(std::size_t(w * h)), anchor(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = vec3(coordinate(rng), coordinate(rng), coordinate(rng));
    anchor[i] = x[i] + vec3(coordinate(rng), coordinate(rng), coordinate(rng)) * 0.01f;
  }
  const GridShape shape = GridShape::of(w, h);
  std::vector<float> padded[6];
  for (std::vector<float>& a : padded)
    a.assign(shape.size, 0.0f);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      for (int c = 0; c < 3; ++c) {
        padded[c][std::size_t(shape.at(u, v))] = x[std::size_t(v * w + u)][c];
        padded[3 + c][std::size_t(shape.at(u, v))] = anchor[std::size_t(v * w + u)][c];
      }
  for (const GridKernels* kern : kernelSets())
    for (const int edge : {8, 9, 13, 16, 17, 24})
      for (const bool in_padded : {false, true}) {
        SCOPED_TRACE(::testing::Message() << kern->name << ", squares of " << edge << (in_padded ? ", padded" : ""));
        const int across = (w + edge - 1) / edge, down = (h + edge - 1) / edge;
        std::vector<float> out(std::size_t(12 * across * down), 0.0f);
        TileBoxArgs args{&x.data()->x, &anchor.data()->x, w, h, edge, across, out.data(), 0, down};
        if (in_padded) {
          args.shape = shape;
          args.px = padded[0].data();
          args.py = padded[1].data();
          args.pz = padded[2].data();
          args.ax = padded[3].data();
          args.ay = padded[4].data();
          args.az = padded[5].data();
        }
        ASSERT_TRUE(kern->tileBoxes(args));
        for (int t = 0; t < across * down; ++t) {
          const int u0 = t % across * edge, v0 = t / across * edge;
          float expect[12];
          for (int c = 0; c < 3; ++c) {
            expect[c] = expect[6 + c] = std::numeric_limits<float>::infinity();
            expect[3 + c] = expect[9 + c] = -std::numeric_limits<float>::infinity();
          }
          for (int v = v0; v < std::min(v0 + edge, h); ++v)
            for (int u = u0; u < std::min(u0 + edge, w); ++u) {
              const std::size_t i = std::size_t(v * w + u);
              for (int c = 0; c < 3; ++c) {
                const float d = x[i][c] - anchor[i][c];
                expect[c] = std::min(expect[c], d);
                expect[3 + c] = std::max(expect[3 + c], d);
                expect[6 + c] = std::min(expect[6 + c], x[i][c]);
                expect[9 + c] = std::max(expect[9 + c], x[i][c]);
              }
            }
          for (int k = 0; k < 12; ++k)
            ASSERT_EQ(out[std::size_t(12 * t + k)], expect[k]) << "tile " << t << ", number " << k;
        }
        // A displacement that is not finite, in the last tile's last point
        const std::size_t last = x.size() - 1;
        const float kept = anchor[last].y;
        anchor[last].y = std::numeric_limits<float>::quiet_NaN();
        padded[4][std::size_t(shape.at(w - 1, h - 1))] = anchor[last].y;
        EXPECT_FALSE(kern->tileBoxes(args));
        anchor[last].y = kept;
        padded[4][std::size_t(shape.at(w - 1, h - 1))] = kept;
      }
}

// CollisionPairs on a grid cloth with the kernels and without (the scalar tiles' comparison) gives the same
// answer at every step of a motion that tears regions apart now and then. Three grids: 37 x 37 (tiles of 8 points with
// 5 left over: partial vectors, and the last row's tail), 37 x 200 (tiles of 13: a partial vector of sixteen) and
// 40 x 272 (tiles of 17: a whole vector of sixteen and one lane more).
TEST(ContactKernels, TheTileComparisonAnswersAsTheScalarOne) {
  const float spacing = 0.02f, range = 0.019f, margin = 0.0095f;
  for (const auto& [n, h] : {std::pair{37, 37}, std::pair{37, 200}, std::pair{40, 272}}) {
    std::vector<vec3> rest;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < n; ++u)
        rest.push_back(vec3(float(u) * spacing, 0.0f, float(v) * spacing));
    for (const GridKernels* kern : kernelSets()) {
      SCOPED_TRACE(::testing::Message() << kern->name << ", " << n << " x " << h);
      CollisionPairs<float> with, without;
      for (CollisionPairs<float>* p : {&with, &without}) {
        p->configure(range, margin);
        p->setRest(rest);
        p->setGrid(n, h);
      }
      with.setKernels(kern);
      std::mt19937 rng(5);
      std::uniform_real_distribution<float> jitter(-0.0004f, 0.0004f);
      std::vector<vec3> x = rest;
      int builds = 0;
      for (int s = 0; s < 400; ++s) {
        // A fold that sweeps across: the rows past a moving line lift and slide against the rest
        const int line = (s / 10) % n;
        for (int v = 0; v < h; ++v)
          for (int u = 0; u < n; ++u) {
            vec3& p = x[std::size_t(v * n + u)];
            p += vec3(jitter(rng), jitter(rng), jitter(rng));
            if (u > line) p.y += 0.0006f;
          }
        const bool a = with.update(x, 1), b = without.update(x, 1);
        ASSERT_EQ(a, b) << "step " << s;
        builds += a;
      }
      EXPECT_EQ(with.closerLooksKept(), without.closerLooksKept());
      EXPECT_GT(builds, 20);   // the motion wore the lists out many times
      EXPECT_LT(builds, 400);  // and not at every step
      EXPECT_TRUE(x87Usable()) << "the tile comparison left the x87 registers to MMX";
    }
  }
}

// filePairs against the build's rule written out: each slot's point, the pair passed over where its offset lies in
// the box and the table does not list it, else {lower, upper | far} to the share of its lower end, in order. Random
// pairs, a third of them offsets in the box (so every kind is met), far marks, a split through the points or past
// them all, and counts that do not fill the last vector.
TEST(ContactKernels, FilePairsKeepsWhatTheBuildsRuleKeepsInOrder) {
  constexpr int kW = 37, kH = 29, kBox = 3, kSide = 2 * kBox + 1;
  const std::uint32_t n = kW * kH;
  std::mt19937 rng(5);
  std::vector<std::uint32_t> sorted(n), uv(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    sorted[i] = i;
    uv[i] = (i % kW) | (i / kW) << 16;
  }
  std::shuffle(sorted.begin(), sorted.end(), rng);
  std::vector<std::uint32_t> slot_of(n);
  for (std::uint32_t s = 0; s < n; ++s)
    slot_of[sorted[s]] = s;
  std::vector<std::int32_t> kind(kSide * kSide);
  for (std::int32_t& k : kind)
    k = std::int32_t(rng() % 3);  // list, held, stencil
  std::uniform_int_distribution<std::uint32_t> any(0, n - 1);
  std::uniform_int_distribution<int> near(-kBox - 1, kBox + 1);
  std::vector<std::uint32_t> points, slots;
  for (int k = 0; k < 1000; ++k) {
    std::uint32_t i = any(rng), j = any(rng);
    if (k % 3 == 0) {  // an offset in (or just off) the box, on the grid
      const int u = std::clamp(int(i % kW) + near(rng), 0, kW - 1), v = std::clamp(int(i / kW) + near(rng), 0, kH - 1);
      j = std::uint32_t(v * kW + u);
    }
    points.push_back(slot_of[i]);
    slots.push_back(slot_of[j] | (rng() % 2 ? kFarSlot : 0));
  }
  for (const int count : {0, 1, 15, 16, 17, 999, 1000})
    for (const std::uint32_t split : {n / 3, ~std::uint32_t(0)}) {
      std::vector<FiledPair> expected[2];
      for (int k = 0; k < count; ++k) {
        const std::uint32_t i = sorted[points[std::size_t(k)]], j = sorted[slots[std::size_t(k)] & ~kFarSlot];
        const int du = int(j % kW) - int(i % kW), dv = int(j / kW) - int(i / kW);
        if (std::abs(du) <= kBox && std::abs(dv) <= kBox && kind[std::size_t((dv + kBox) * kSide + du + kBox)] != 0)
          continue;
        const FiledPair pair{std::min(i, j), std::max(i, j) | (slots[std::size_t(k)] & kFarSlot)};
        expected[pair.lower >= split].push_back(pair);
      }
      if (split > n) {
        ASSERT_TRUE(expected[1].empty());
      }
      for (const GridKernels* kern : kernelSets()) {
        SCOPED_TRACE(std::string(kern->name) + " count " + std::to_string(count) + " split " + std::to_string(split));
        const PairFileArgs args{sorted.data(), uv.data(), kind.data(), kBox, split};
        std::vector<FiledPair> got[2];
        for (std::vector<FiledPair>& g : got)
          g.assign(std::size_t(count) + kPairScanPad, FiledPair{7, 7});
        FiledPair* const out[2] = {got[0].data(), split > n ? nullptr : got[1].data()};
        int counts[2] = {-1, -1};
        kern->filePairs(args, points.data(), slots.data(), count, out, counts);
        for (int d = 0; d < 2; ++d) {
          ASSERT_EQ(counts[d], int(expected[d].size())) << "share " << d;
          for (std::size_t k = 0; k < expected[d].size(); ++k) {
            EXPECT_EQ(got[d][k].lower, expected[d][k].lower) << "share " << d << " pair " << k;
            EXPECT_EQ(got[d][k].upper, expected[d][k].upper) << "share " << d << " pair " << k;
          }
        }
      }
    }
}

}  // namespace
}  // namespace drape
