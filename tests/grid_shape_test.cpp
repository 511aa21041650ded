// The grid path's padded layout (GridShape) and its arrays: where rows start, and the room around them.
#include "core/scene.hpp"
#include "core/topology.hpp"
#include "cpu/grid_path.hpp"
#include "test_paths.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace drape {
namespace {

// Every row of the padded arrays starts on a cache line, for any width: the stride and the left padding are whole
// lines of floats, the arrays start on one (cpu/aligned.hpp), and the right padding holds two vectors of the widest
// set past a row's last point.
TEST(GridShape, EveryRowStartsOnACacheLine) {
  for (const int w : {2, 7, 16, 50, 129, 256, 1000}) {
    SCOPED_TRACE(w);
    const GridShape g = GridShape::of(w, 5);
    EXPECT_GE(g.stride, w + GridShape::kLeft + 2 * GridShape::kMaxWidth);
    for (int y = 0; y < g.H; ++y)
      EXPECT_EQ(g.at(0, y) % 16, 0);
    Scene scene = loadScene(std::string(drape::test::sourceDir()) + "/scenes/pinned2.json");
    scene.cloth.num_width_points = w;
    scene.cloth.num_height_points = 5;
    scene.cloth.pinned.clear();  // the file's pins lie past narrower grids
    const Topology topo = buildTopology(scene.cloth);
    std::vector<float> rest;
    for (const Spring& s : topo.springs)
      rest.push_back(float(s.rest));
    const GridPath path(topo, rest, GridIsa::Auto);
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(path.positions(c)) % 64, 0u);
  }
}

}  // namespace
}  // namespace drape
