// The grid is one generator of the cloth's mesh representation (Topology: positions, springs, per-point
// area and mass, the wind's normal stencil), and every bundled scene must give the same positions as
// before that representation existed. The fingerprints below are FNV-1a 64 of `drape simulate SCENE
// --frames 90 --solver cpu --threads 1 --out FILE` written by the grid-only generator (the commit before
// the mesh cloth, 85f5cbc); tools/compare-outputs compares the two builds byte for byte on more frames.
// The GPU equals the CPU float solver bit for bit on llvmpipe (tests/gpu_runs_gl_test.cpp), so it is
// covered through them.
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
  const fs::path dir = fs::temp_directory_path() / ("drape_grid_golden_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path out = dir / (std::string(GetParam().scene) + ".json");
  const std::string cmd = std::string(DRAPE_BINARY) + " simulate " + DRAPE_SOURCE_DIR + "/scenes/" + GetParam().scene +
                          ".json --frames 90 --solver cpu --threads 1 --out " + out.string() + " >/dev/null 2>&1";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << cmd;
  std::ifstream in(out, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_EQ(fnv1a(bytes.str()), GetParam().fingerprint) << GetParam().scene;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, GridGolden,
    ::testing::Values(Golden{"pinned2", 0x3469f6c6d5b42baeULL}, Golden{"pinned4", 0x82c74843ee6e3c3dULL},
                      Golden{"plane", 0x39d08852338e4846ULL}, Golden{"selfCollision", 0x945b5156f4ecfd78ULL},
                      Golden{"sphere", 0x00f59007e465e5b8ULL}, Golden{"two_spheres", 0x7ac1bbc2b85b63d6ULL},
                      Golden{"wind", 0x1f839187ac670dabULL}),
    [](const ::testing::TestParamInfo<Golden>& p) { return std::string(p.param.scene); });

}  // namespace
