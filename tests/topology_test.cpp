#include "core/topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

namespace drape {
namespace {

ClothSpec grid(int w, int h, Orientation o = Orientation::Horizontal) {
  ClothSpec c;
  c.num_width_points = w;
  c.num_height_points = h;
  c.orientation = o;
  return c;
}

std::size_t structuralCount(int W, int H) {
  return std::size_t(2 * W * H - W - H);
}
std::size_t shearingCount(int W, int H) {
  return std::size_t(2 * (W - 1) * (H - 1));
}
std::size_t bendingCount(int W, int H) {
  return std::size_t(2 * W * H - 2 * W - 2 * H);
}

TEST(Topology, SpringCountsOf50x50MatchCs184) {
  Topology t = buildTopology(grid(50, 50));
  EXPECT_EQ(t.springCount(SpringType::Structural), 4900u);
  EXPECT_EQ(t.springCount(SpringType::Shearing), 4802u);
  EXPECT_EQ(t.springCount(SpringType::Bending), 4800u);
  EXPECT_EQ(t.springs.size(), 14502u);
}

struct GridCase {
  const char* name;
  int W, H;
};

class TopologyGrid : public ::testing::TestWithParam<GridCase> {};

TEST_P(TopologyGrid, CountsAdjacencyAndTriangles) {
  const auto [name, W, H] = GetParam();
  Topology t = buildTopology(grid(W, H));
  EXPECT_EQ(t.springCount(SpringType::Structural), structuralCount(W, H)) << name;
  EXPECT_EQ(t.springCount(SpringType::Shearing), shearingCount(W, H)) << name;
  EXPECT_EQ(t.springCount(SpringType::Bending), bendingCount(W, H)) << name;
  ASSERT_EQ(t.offsets.size(), std::size_t(W * H + 1));
  EXPECT_EQ(t.adjacency.size(), 2 * t.springs.size()) << "each spring appears once at each end";
  EXPECT_EQ(t.triangles.size(), std::size_t(6 * (W - 1) * (H - 1)));

  std::set<std::pair<std::uint32_t, std::uint32_t>> unique;
  for (const Spring& s : t.springs) {
    EXPECT_LT(s.a, s.b);
    EXPECT_TRUE(unique.insert({s.a * 4 + std::uint32_t(s.type), s.b}).second) << "duplicate spring";
    EXPECT_NEAR(s.rest, glm::distance(t.initial_positions[s.a], t.initial_positions[s.b]), 1e-15);
  }
  for (int i = 0; i < W * H; ++i)
    for (std::uint32_t e = t.offsets[i]; e + 1 < t.offsets[i + 1]; ++e)
      EXPECT_LT(t.adjacency[e].spring, t.adjacency[e + 1].spring) << "adjacency order is ascending spring index";
}

// A grid's adjacency, made from its layout, is entry for entry the one made from its springs (buildAdjacency), and
// each entry is its spring seen from the point that lists it.
TEST_P(TopologyGrid, AdjacencyFromTheLayoutIsTheSpringsOwn) {
  const auto [name, W, H] = GetParam();
  const Topology t = buildTopology(grid(W, H));
  Topology from_springs = t;
  from_springs.offsets.clear();
  from_springs.adjacency.clear();
  buildAdjacency(from_springs);
  ASSERT_EQ(t.offsets, from_springs.offsets) << name;
  ASSERT_EQ(t.adjacency.size(), from_springs.adjacency.size()) << name;
  for (std::size_t e = 0; e < t.adjacency.size(); ++e) {
    const Neighbor &a = t.adjacency[e], &b = from_springs.adjacency[e];
    ASSERT_EQ(a.other, b.other) << name << ", entry " << e;
    ASSERT_EQ(a.spring, b.spring) << name << ", entry " << e;
    ASSERT_EQ(a.type, b.type) << name << ", entry " << e;
    ASSERT_EQ(a.rest, b.rest) << name << ", entry " << e;
  }
  for (int i = 0; i < W * H; ++i)
    for (std::uint32_t e = t.offsets[i]; e < t.offsets[i + 1]; ++e) {
      const Spring& s = t.springs[t.adjacency[e].spring];
      EXPECT_TRUE((s.a == std::uint32_t(i) && s.b == t.adjacency[e].other) ||
                  (s.b == std::uint32_t(i) && s.a == t.adjacency[e].other))
          << name << ", point " << i;
    }
}

INSTANTIATE_TEST_SUITE_P(Grids, TopologyGrid,
                         ::testing::Values(GridCase{"square", 50, 50}, GridCase{"wide", 7, 3}, GridCase{"tall", 2, 9},
                                           GridCase{"smallest", 2, 2}, GridCase{"thin", 13, 2},
                                           GridCase{"narrow", 3, 17}),
                         [](const auto& row) { return std::string(row.param.name); });

TEST(Topology, InteriorPointHasTwelveNeighbours) {
  Topology t = buildTopology(grid(9, 9));
  const int i = 4 * 9 + 4;
  EXPECT_EQ(t.offsets[i + 1] - t.offsets[i], 12u);  // 4 structural, 4 shearing, 4 bending
}

TEST(Topology, HorizontalClothLiesAtHeightOneAndFacesUp) {
  ClothSpec c = grid(5, 4);
  c.width = 2.0;
  c.height = 3.0;
  Topology t = buildTopology(c);
  for (const glm::dvec3& p : t.initial_positions)
    EXPECT_EQ(p.y, 1.0);
  EXPECT_EQ(t.initial_positions.back(), glm::dvec3(2.0, 1.0, 3.0));
  for (std::size_t k = 0; k < t.triangles.size(); k += 3) {
    glm::dvec3 a = t.initial_positions[t.triangles[k]], b = t.initial_positions[t.triangles[k + 1]],
               d = t.initial_positions[t.triangles[k + 2]];
    EXPECT_GT(glm::cross(b - a, d - a).y, 0.0);
  }
}

TEST(Topology, VerticalOffsetsAreSmallDeterministicAndVaried) {
  Topology a = buildTopology(grid(20, 20, Orientation::Vertical));
  Topology b = buildTopology(grid(20, 20, Orientation::Vertical));
  std::set<double> distinct;
  for (std::size_t i = 0; i < a.initial_positions.size(); ++i) {
    EXPECT_EQ(a.initial_positions[i], b.initial_positions[i]);
    EXPECT_LE(std::abs(a.initial_positions[i].z), 1e-3);
    distinct.insert(a.initial_positions[i].z);
  }
  EXPECT_GT(distinct.size(), 390u);
}

TEST(Topology, Pins) {
  ClothSpec c = grid(50, 50);
  c.pinned = {{0, 0}, {49, 0}, {3, 7}};
  Topology t = buildTopology(c);
  EXPECT_EQ(std::count(t.pinned.begin(), t.pinned.end(), 1), 3);
  EXPECT_EQ(t.pinned[7 * 50 + 3], 1);
}

// A ClothSpec changed in code after its scene was read (a test resizing a bundled cloth, say) is not validated again:
// a pin off the grid, or a vertex pin past the points, once wrote past the pin array. Each is one clear error now.
TEST(Topology, APinOffTheGridIsAnErrorNotAWritePastTheArray) {
  for (const glm::ivec2 pin : {glm::ivec2(50, 0), glm::ivec2(0, 50), glm::ivec2(-1, 3), glm::ivec2(3, -1)}) {
    ClothSpec c = grid(50, 50);
    c.pinned = {{0, 0}, pin};
    try {
      (void)buildTopology(c);
      ADD_FAILURE() << "no error for the pin [" << pin.x << ", " << pin.y << "]";
    } catch (const std::invalid_argument& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find("[" + std::to_string(pin.x) + ", " + std::to_string(pin.y) + "]"), std::string::npos) << text;
      EXPECT_NE(text.find("50 x 50"), std::string::npos) << text;
    }
  }
  ClothSpec c = grid(10, 10);
  c.pinned_vertices = {99};
  const Topology last = buildTopology(c);  // the last point, pinned by index
  EXPECT_EQ(std::count(last.pinned.begin(), last.pinned.end(), 1), 1);
  EXPECT_EQ(last.pinned[99], 1);
  c.pinned_vertices = {100};
  EXPECT_THROW((void)buildTopology(c), std::invalid_argument);
  EXPECT_THROW((void)buildTopology(grid(1, 5)), std::invalid_argument);
  EXPECT_THROW((void)buildTopology(grid(5, 1)), std::invalid_argument);
}

TEST(Topology, SpringsAreReservedExactlyNotGrownByDoubling) {
  // Growing the largest cloth's 25 million springs doubled their memory while copying; the count is
  // known up front.
  for (auto [w, h] : {std::pair{2, 2}, std::pair{3, 7}, std::pair{50, 50}, std::pair{129, 64}}) {
    const Topology t = buildTopology(grid(w, h));
    EXPECT_EQ(t.springs.capacity(), t.springs.size()) << w << " x " << h;
  }
}

}  // namespace
}  // namespace drape
