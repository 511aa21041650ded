// The grid is one generator of the cloth's mesh representation (Topology: positions, springs, per-point
// area and mass, the wind's normal stencil), and every bundled scene must give the same positions as
// before that representation existed. The fingerprints below are FNV-1a 64 of `drape simulate SCENE
// --frames 90 --solver cpu --threads 1 --out FILE`. They were those of the grid-only generator (the commit
// before the mesh cloth, 85f5cbc) until the grid's spring colouring became direction and parity (for the
// tiled stretch kernel, src/core/colouring.hpp): that changed the Gauss-Seidel order of the border
// springs, and every scene whose cloth reaches the stretch limit (all but plane) was fingerprinted again
// with the commit that made the change; and sphere and two_spheres again when the collisions were
// repeated after the stretch limit (issue 26, collide_last: the limit had left points inside the spheres).
// tools/compare-outputs compares two builds byte for byte on more frames.
// The GPU equals the CPU float solver bit for bit on llvmpipe (tests/gpu_runs_gl_test.cpp), so it is
// covered through them.
#include "test_paths.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

struct Golden {
  const char* scene;
  std::uint64_t fingerprint;
};

class GridGolden : public ::testing::TestWithParam<Golden> {};

TEST_P(GridGolden, BundledSceneGivesThePositionsOfTheGridOnlyGenerator) {
  const drape::test::TempDir dir("drape_grid_golden_");
  const fs::path out = dir.path() / (std::string(GetParam().scene) + ".json");
  const std::string cmd = std::string(drape::test::drapeBinary()) + " simulate " + drape::test::sourceDir() +
                          "/scenes/" + GetParam().scene + ".json --frames 90 --solver cpu --threads 1 --out " +
                          out.string() + " >/dev/null 2>&1";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << cmd;
  std::ifstream in(out, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(fnv1a(bytes.str()), GetParam().fingerprint) << GetParam().scene;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GridGolden,
    ::testing::Values(Golden{"pinned2", 0x766cee0a81c836e6ULL}, Golden{"pinned4", 0xe029c075e6e7ddd6ULL},
                      Golden{"plane", 0x39d08852338e4846ULL}, Golden{"selfCollision", 0x966aa3b4f80ba19aULL},
                      Golden{"sphere", 0x5945610707ca2fd4ULL}, Golden{"two_spheres", 0xeb15b935df9f1e0aULL},
                      Golden{"wind", 0x82c0ae6dc5299e68ULL}),
    [](const ::testing::TestParamInfo<Golden>& p) { return std::string(p.param.scene); });

}  // namespace
