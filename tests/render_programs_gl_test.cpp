// The renderer's building blocks: every shading program compiles, links and declares exactly the
// uniforms it uses; a failed reload keeps the old program; textures fail loudly; collider meshes and
// the camera (pure CPU, no context needed).
#include "gl/debug.hpp"
#include "gl/shader.hpp"
#include "gl_fixture.hpp"
#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/mesh_data.hpp"
#include "render/shading_program.hpp"
#include "render/texture_set.hpp"
#include "test_paths.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>

namespace drape {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

// Sets an environment variable for the scope of the object.
struct ScopedEnv {
  std::string name;
  ScopedEnv(std::string n, const std::string& value) : name(std::move(n)) { ::setenv(name.c_str(), value.c_str(), 1); }
  ~ScopedEnv() { ::unsetenv(name.c_str()); }
};

std::set<std::string> activeUniforms(GLuint program) {
  GLint count = 0;
  glGetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
  std::set<std::string> names;
  for (GLint i = 0; i < count; ++i) {
    char name[256];
    GLsizei length = 0;
    GLint size = 0;
    GLenum type = 0;
    glGetActiveUniform(program, GLuint(i), sizeof name, &length, &size, &type, name);
    names.insert(std::string(name, std::size_t(length)));
  }
  return names;
}

class ProgramTest : public GlTest, public ::testing::WithParamInterface<ProgramId> {};

TEST_P(ProgramTest, CompilesLinksAndDeclaresExactlyTheUniformsItUses) {
  const ProgramSpec& spec = programSpec(GetParam());
  ShadingProgram program(spec);
  ASSERT_NE(program.program().id(), 0u);
  GLint linked = GL_FALSE;
  glGetProgramiv(program.program().id(), GL_LINK_STATUS, &linked);
  EXPECT_EQ(linked, GL_TRUE);
  // A declared uniform the shader does not use would be silently skipped; one it uses but the renderer
  // never declared could never be set. On llvmpipe both sets must agree exactly.
  const std::set<std::string> declared(spec.uniforms.begin(), spec.uniforms.end());
  EXPECT_EQ(declared, activeUniforms(program.program().id())) << spec.name;
}

std::vector<ProgramId> allPrograms() {
  std::vector<ProgramId> ids;
  for (const ProgramSpec& spec : programSpecs())
    ids.push_back(spec.id);
  return ids;
}

INSTANTIATE_TEST_SUITE_P(Every, ProgramTest, ::testing::ValuesIn(allPrograms()),
                         [](const auto& test) { return programSpec(test.param).name; });

TEST(ProgramSpecs, CoverEveryShadingForClothAndColliders) {
  for (Shading s : allShadings()) {
    EXPECT_EQ(programSpec(clothProgram(s)).name, shadingName(s));
    EXPECT_NE(colliderProgram(s), ProgramId::Wireframe);  // colliders are surfaces in every model
  }
  for (int i = 0; i < kProgramCount; ++i)
    EXPECT_EQ(int(programSpecs()[std::size_t(i)].id), i);
}

using ShadingProgramTest = GlTest;

TEST_F(ShadingProgramTest, SettingAnUndeclaredUniformThrows) {
  ShadingProgram phong(programSpec(ProgramId::Phong));
  EXPECT_NO_THROW(phong.set("u_colour", glm::vec3(1.0f)));
  EXPECT_THROW(phong.set("u_color", glm::vec3(1.0f)), gl::GlError);
  EXPECT_THROW(phong.set("u_shadow_map", 3), gl::GlError);  // declared by another program only
}

TEST_F(ShadingProgramTest, FailedReloadKeepsTheOldProgramAndReportsFileAndLine) {
  ProgramSet programs = ProgramSet::compileAll();
  const GLuint old_phong = programs[ProgramId::Phong].program().id();
  const GLuint old_normal = programs[ProgramId::Normal].program().id();

  TempDir dir("drape_broken_glsl_");
  fs::copy(gl::glslRoot(), dir.path(), fs::copy_options::recursive);
  {
    std::ofstream broken(dir.path() / "render" / "phong.frag", std::ios::app);
    broken << "\nvoid broken() { this is not glsl; }\n";
  }
  std::string errors;
  {
    ScopedEnv env("DRAPE_GLSL_DIR", dir.path().string());
    errors = programs.reload();
  }
  EXPECT_NE(errors.find("phong.frag:"), std::string::npos) << errors;
  EXPECT_EQ(errors.find("normal.frag"), std::string::npos) << errors;
  EXPECT_EQ(programs[ProgramId::Phong].program().id(), old_phong);      // kept
  EXPECT_NE(programs[ProgramId::Normal].program().id(), old_normal);    // recompiled
  EXPECT_TRUE(glIsProgram(programs[ProgramId::Phong].program().id()));  // and still alive

  EXPECT_EQ(programs.reload(), "");  // back on the real sources, every program compiles again
  EXPECT_NE(programs[ProgramId::Phong].program().id(), old_phong);
}

using TextureTest = GlTest;

TEST_F(TextureTest, CommittedTexturesLoad) {
  const TextureSet set = TextureSet::load();
  EXPECT_GE(set.fabric.width(), 256);
  EXPECT_GT(set.fabric.levels(), 1);  // mipmapped
  EXPECT_EQ(set.sky.target(), GLenum(GL_TEXTURE_CUBE_MAP));
  EXPECT_EQ(set.cobblestone.width(), set.cobblestone.height());
}

TEST_F(TextureTest, MissingOrCorruptTextureNamesTheFile) {
  TempDir dir("drape_textures_");
  try {
    TextureSet::load(dir.path());
    FAIL() << "loading from an empty directory succeeded";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find((dir.path() / "fabric.png").string()), std::string::npos) << e.what();
  }
  fs::copy(textureDir(), dir.path(), fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  { std::ofstream(dir.path() / "brick_height.png", std::ios::trunc) << "not a png"; }
  try {
    TextureSet::load(dir.path());
    FAIL() << "a corrupt brick_height.png loaded";
  } catch (const ImageError& e) {
    EXPECT_NE(std::string(e.what()).find("brick_height.png"), std::string::npos) << e.what();
  }
}

TEST(SphereMesh, CountsAndOutwardCounterClockwiseTriangles) {
  for (auto [lat, lon] : {std::pair{40, 40}, std::pair{2, 3}, std::pair{7, 13}}) {
    const MeshData mesh = buildSphereMesh(lat, lon);
    EXPECT_EQ(mesh.vertexCount(), std::size_t((lat + 1) * (lon + 1)));
    EXPECT_EQ(mesh.triangles.size(), std::size_t(3 * 2 * lon * (lat - 1)));
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
      EXPECT_NEAR(glm::length(glm::vec3(mesh.positions[i])), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(glm::vec3(mesh.normals[i]), glm::vec3(mesh.positions[i])), 1.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(glm::vec3(mesh.tangents[i]), glm::vec3(mesh.normals[i])), 0.0f, 1e-5f);
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
      const glm::vec3 a(mesh.positions[mesh.triangles[t]]), b(mesh.positions[mesh.triangles[t + 1]]),
          c(mesh.positions[mesh.triangles[t + 2]]);
      const glm::vec3 n = glm::cross(b - a, c - a);
      ASSERT_GT(glm::length(n), 0.0f) << "degenerate triangle " << t / 3;
      EXPECT_GT(glm::dot(n, a + b + c), 0.0f) << "triangle " << t / 3 << " faces inwards";
    }
  }
  EXPECT_THROW(buildSphereMesh(1, 40), std::invalid_argument);
  EXPECT_THROW(buildSphereMesh(40, 2), std::invalid_argument);
}

TEST(PlaneMesh, SquareFacingItsNormal) {
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  const MeshData mesh = buildPlaneMesh({1, 2, 3}, n, 10.0f);
  ASSERT_EQ(mesh.vertexCount(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 6u);
  for (const glm::vec4& p : mesh.positions)
    EXPECT_NEAR(glm::dot(glm::vec3(p) - glm::vec3(1, 2, 3), n), 0.0f, 1e-5f);
  for (std::size_t t = 0; t < 6; t += 3) {
    const glm::vec3 a(mesh.positions[mesh.triangles[t]]), b(mesh.positions[mesh.triangles[t + 1]]),
        c(mesh.positions[mesh.triangles[t + 2]]);
    EXPECT_NEAR(glm::dot(glm::normalize(glm::cross(b - a, c - a)), n), 1.0f, 1e-5f);
  }
  EXPECT_NEAR(glm::distance(glm::vec3(mesh.positions[0]), glm::vec3(mesh.positions[3])), 10.0f * std::sqrt(2.0f),
              1e-4f);
}

// Every corner of the bounds lands inside the view, whatever the window's shape.
TEST(CameraTest, FramingKeepsTheBoundsInView) {
  const Bounds bounds{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
  for (float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 2.5f}) {
    Camera camera;
    camera.frame(bounds, aspect);
    const glm::mat4 vp = camera.viewProjection(aspect);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p{float(corner & 1), float((corner >> 1) & 1), float((corner >> 2) & 1)};
      const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
      ASSERT_GT(clip.w, 0.0f);
      const glm::vec3 ndc = glm::vec3(clip) / clip.w;
      EXPECT_LT(std::abs(ndc.x), 1.0f) << "aspect " << aspect << " corner " << corner;
      EXPECT_LT(std::abs(ndc.y), 1.0f) << "aspect " << aspect << " corner " << corner;
      EXPECT_LT(std::abs(ndc.z), 1.0f);
    }
  }
}

TEST(CameraTest, OrbitPanZoomAndRays) {
  Camera camera;
  camera.frame({{0, 0, 0}, {1, 1, 1}}, 1.0f);
  const glm::vec3 target = camera.target();
  const float distance = camera.distance();
  camera.orbit(0.7f, -0.3f);
  EXPECT_NEAR(glm::distance(camera.position(), target), distance, 1e-4f);  // orbit keeps the distance
  camera.orbit(0.0f, 100.0f);                                              // pitch is clamped short of the pole
  EXPECT_LT(glm::dot(glm::normalize(camera.position() - target), glm::vec3(0, 1, 0)), 1.0f);
  camera.zoom(0.5f);
  EXPECT_NEAR(camera.distance(), 0.5f * distance, 1e-5f);

  // A ray through the centre of the viewport goes through the target.
  const Ray centre = camera.rayThrough({200.0f, 150.0f}, {400, 300});
  const glm::vec3 to_target = glm::normalize(camera.target() - centre.origin);
  EXPECT_NEAR(glm::dot(centre.direction, to_target), 1.0f, 1e-5f);
  // Panning by a drag moves the target perpendicular to the view, by the distance the drag covers there.
  const glm::vec3 before = camera.target();
  camera.pan(100.0f, 0.0f, 300.0f);
  const glm::vec3 moved = camera.target() - before;
  EXPECT_NEAR(glm::dot(moved, glm::normalize(camera.position() - camera.target())), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(moved), 100.0f / 300.0f * 2.0f * camera.distance() * std::tan(0.5f * Camera::kFovY), 1e-4f);
}

}  // namespace
}  // namespace drape
