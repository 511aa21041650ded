// The kernels are specialised per scene with #defines, so that code for a feature the scene does not
// have is not in what the compiler compiles. Checked here: the defines each bundled scene yields, and
// the kernels' text after preprocessing with them (glslangValidator -E: the #if blocks resolved, as
// the driver's compiler resolves them), where each feature's code must appear exactly when the scene
// has the feature. GL's own introspection cannot tell: Mesa reports every declared storage block as
// active and none as referenced, used or not.
#include "gl/shader.hpp"
#include "gl/shader_source.hpp"
#include "gl_fixture.hpp"
#include "gpu/gpu_solver.hpp"
#include "gpu_test_support.hpp"
#include "test_paths.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

namespace drape {
namespace {

namespace fs = std::filesystem;

struct VariantCase {
  const char* scene;
  int spheres, planes;
  bool self_collision, wind;
};

void PrintTo(const VariantCase& c, std::ostream* os) {
  *os << c.scene;
}

int occurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

class GpuVariantTest : public GlTest, public ::testing::WithParamInterface<VariantCase> {
 protected:
  // The kernel as the compiler sees it after its own preprocessor ran: our loader's text (version,
  // defines, includes), then glslangValidator -E. Empty when glslangValidator is not installed.
  static std::string compiledText(const char* kernel, const gl::Defines& defines) {
    const fs::path validator = DRAPE_GLSLANG;
    if (!fs::exists(validator)) return {};
    const gl::ShaderSource source = gl::preprocess(gl::glslRoot() / "sim" / kernel, defines, gl::glslRoot());
    const test::TempDir dir("drape_variants_");
    const fs::path in = dir.path() / "kernel.comp", out = dir.path() / "kernel.txt";
    std::ofstream(in) << source.text;
    const std::string command = validator.string() + " -E -S comp " + in.string() + " > " + out.string() + " 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << kernel << ": " << command;
    std::stringstream text;
    text << std::ifstream(out).rdbuf();
    return text.str();
  }
};

TEST_P(GpuVariantTest, SceneYieldsItsDefinesAndOnlyItsFeaturesCode) {
  const VariantCase& c = GetParam();
  GpuSolver gpu(gpu_test::standardScene(c.scene));
  const gl::Defines expected = {{"NUM_SPHERES", std::to_string(c.spheres)},
                                {"NUM_PLANES", std::to_string(c.planes)},
                                {"SELF_COLLISION", c.self_collision ? "1" : "0"},
                                {"WIND", c.wind ? "1" : "0"},
                                {"UNIFORM_MASS", "1"}};  // every standard scene is a grid: one weight for all
  EXPECT_EQ(gpu.defines(), expected);

  // The compiled program: the wind's time uniform exists only with wind.
  const gl::Program integrate =
      gl::compileCompute("sim/forces_integrate.comp", gpu.kernelDefines(gpu::Pass::ForcesIntegrate));
  EXPECT_EQ(integrate.hasUniform("u_time"), c.wind);

  const std::string text = compiledText("forces_integrate.comp", gpu.kernelDefines(gpu::Pass::ForcesIntegrate));
  if (text.empty()) GTEST_SKIP() << "glslangValidator not found (" << DRAPE_GLSLANG << "): only the defines checked";
  ASSERT_NE(text.find("void main()"), std::string::npos) << text.substr(0, 2000);
  // The integrate kernel counts points into the hash grid only when self-collision follows, reads the
  // wind only with wind, and collides (its call in main) only when there are colliders and no
  // self-collision pass to do it later. collideObjects itself is always defined (empty without
  // colliders), hence the 1.
  const bool colliders = c.spheres + c.planes > 0;
  EXPECT_EQ(occurrences(text, "checkPairTravel("), c.self_collision ? 2 : 0);  // definition and call
  EXPECT_EQ(occurrences(text, "pairAnchor") > 0, c.self_collision);
  EXPECT_EQ(occurrences(text, "gridCounts"), 0) << "the lists' grid is built only when they are stale";
  EXPECT_EQ(occurrences(text, "u_time") > 0, c.wind);
  EXPECT_EQ(occurrences(text, "pointNormal(") > 0, c.wind);
  EXPECT_EQ(occurrences(text, "collideObjects("), 1 + (colliders && !c.self_collision ? 1 : 0));
  // The buffer's declaration, then one read per collider loop.
  EXPECT_EQ(occurrences(text, "colliders["), 1 + (colliders ? 2 : 0));
  if (colliders) {
    // Each loop runs over the scene's own count: a collider type it lacks is a loop of constant trip
    // count 0, which no compiler keeps.
    EXPECT_EQ(occurrences(text, "s < " + std::to_string(c.spheres) + ";"), 1) << "sphere loop";
    EXPECT_EQ(occurrences(text, "p < " + std::to_string(c.planes) + ";"), 1) << "plane loop";
  }
  if (c.self_collision) {
    const std::string self = compiledText("self_collide.comp", gpu.kernelDefines(gpu::Pass::SelfCollide));
    EXPECT_EQ(occurrences(self, "collideObjects("), 1 + (colliders ? 1 : 0));
  }
}

// clang-format off
INSTANTIATE_TEST_SUITE_P(Scenes, GpuVariantTest, ::testing::Values(
    VariantCase{"pinned2.json", 0, 0, false, false},
    VariantCase{"pinned4.json", 0, 0, false, false},
    VariantCase{"sphere.json", 1, 0, true, false},
    VariantCase{"plane.json", 0, 1, true, false},
    VariantCase{"selfCollision.json", 0, 1, true, false},
    VariantCase{"wind.json", 0, 0, false, true},
    VariantCase{"two_spheres.json", 2, 1, true, false}),
  [](const ::testing::TestParamInfo<VariantCase>& p) {
    std::string name = p.param.scene;
    return name.substr(0, name.find('.'));
  });
// clang-format on

}  // namespace
}  // namespace drape
