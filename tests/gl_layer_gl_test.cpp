// The GL layer on a real context: context info, buffers, move-only ownership, compute dispatch,
// shader error locations, uniform checking, framebuffers, textures and the timer-query probe.
#include "gl/objects.hpp"
#include "gl/shader.hpp"
#include "gl_fixture.hpp"

#include <fstream>
#include <type_traits>

namespace drape {
namespace {

// Move-only and usable without a context: checked at compile time, no GL needed.
template <class T>
constexpr bool kMoveOnly =
    !std::is_copy_constructible_v<T> && !std::is_copy_assignable_v<T> && std::is_nothrow_move_constructible_v<T> &&
    std::is_nothrow_move_assignable_v<T> && std::is_nothrow_default_constructible_v<T>;
static_assert(kMoveOnly<gl::Buffer>);
static_assert(kMoveOnly<gl::Program>);
static_assert(kMoveOnly<gl::Texture>);
static_assert(kMoveOnly<gl::Renderbuffer>);
static_assert(kMoveOnly<gl::Framebuffer>);
static_assert(kMoveOnly<gl::VertexArray>);
static_assert(kMoveOnly<gl::Query>);
static_assert(!std::is_copy_constructible_v<gl::HeadlessContext> &&
              std::is_nothrow_move_constructible_v<gl::HeadlessContext>);
static_assert(!std::is_copy_constructible_v<gl::WindowContext> &&
              std::is_nothrow_move_constructible_v<gl::WindowContext>);

std::vector<float> sampleValues(std::size_t count) {
  std::vector<float> values(count);
  for (std::size_t i = 0; i < count; ++i)
    values[i] = static_cast<float>(i) * 0.37f - 100.0f;
  return values;
}

// 1-based number of the first line of `file` containing `marker`.
int lineOf(const std::filesystem::path& file, const std::string& marker) {
  std::ifstream in(file);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number)
    if (line.find(marker) != std::string::npos) return number;
  return 0;
}

using GlLayer = GlTest;

TEST(GlObjects, DefaultConstructedObjectsAreEmptyWithoutAContext) {
  const gl::Buffer buffer;
  const gl::Program program;
  const gl::Framebuffer framebuffer;
  EXPECT_EQ(buffer.id(), 0u);
  EXPECT_EQ(buffer.size(), 0u);
  EXPECT_EQ(program.id(), 0u);
  EXPECT_EQ(framebuffer.id(), 0u);
}

TEST_F(GlLayer, ContextIsGl45CoreWithARenderer) {
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 45);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
  EXPECT_FALSE(info().renderer.empty());
  EXPECT_FALSE(info().vendor.empty());
  EXPECT_NE(gl::describe(info()).find(info().renderer), std::string::npos);
  EXPECT_EQ(info().software, info().renderer.find("llvmpipe") != std::string::npos ||
                                 info().renderer.find("softpipe") != std::string::npos ||
                                 info().renderer.find("swrast") != std::string::npos ||
                                 info().renderer.find("SWR") != std::string::npos ||
                                 info().renderer.find("Software Rasterizer") != std::string::npos);
}

TEST_F(GlLayer, BufferRoundTripsUploadsAndClears) {
  const std::vector<float> values = sampleValues(1000);
  gl::Buffer buffer = gl::Buffer::fromVector(values);
  EXPECT_EQ(buffer.size(), values.size() * sizeof(float));
  EXPECT_EQ(buffer.download<float>(values.size()), values);

  const std::vector<float> patch = {1.5f, -2.5f, 3.25f};
  buffer.upload(patch, 10);
  const std::vector<float> window = buffer.download<float>(5, 9);
  EXPECT_EQ(window, (std::vector<float>{values[9], 1.5f, -2.5f, 3.25f, values[13]}));

  gl::Buffer copy = gl::Buffer::create(buffer.size());
  buffer.copyTo(copy, 0, 0, buffer.size());
  EXPECT_EQ(copy.download<float>(values.size()), buffer.download<float>(values.size()));

  buffer.clear();
  EXPECT_EQ(buffer.download<float>(values.size()), std::vector<float>(values.size(), 0.0f));

  EXPECT_THROW(buffer.download<float>(2, values.size() - 1), std::out_of_range);
  EXPECT_THROW(buffer.upload(buffer.size(), 1, patch.data()), std::out_of_range);
}

TEST_F(GlLayer, EmptyBufferIsValidAndReportsSizeZero) {
  gl::Buffer empty = gl::Buffer::fromVector(std::vector<float>{});
  EXPECT_NE(empty.id(), 0u);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_TRUE(empty.download<float>(0).empty());
  empty.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
}

TEST_F(GlLayer, MovedFromObjectIsEmptyAndTheNameIsDeletedOnce) {
  gl::Buffer first = gl::Buffer::create(64);
  const GLuint name = first.id();
  ASSERT_NE(name, 0u);
  {
    gl::Buffer second = std::move(first);
    EXPECT_EQ(first.id(), 0u);  // NOLINT(bugprone-use-after-move): the moved-from state is the point
    EXPECT_EQ(second.id(), name);
    EXPECT_TRUE(glIsBuffer(name));
  }
  EXPECT_FALSE(glIsBuffer(name));  // deleted by `second`; `first` (id 0) deletes nothing

  gl::Buffer target = gl::Buffer::create(16);
  const GLuint replaced = target.id();
  gl::Buffer source = gl::Buffer::create(32);
  const GLuint kept = source.id();
  target = std::move(source);
  EXPECT_FALSE(glIsBuffer(replaced));  // move assignment frees what the target held
  EXPECT_EQ(target.id(), kept);
  EXPECT_EQ(target.size(), 32u);
  EXPECT_EQ(source.id(), 0u);  // NOLINT(bugprone-use-after-move)
}

TEST_F(GlLayer, ComputeDispatchDoublesEveryValueExactly) {
  const gl::Program program = gl::compileCompute(testShader("double_values.comp"), {{"FACTOR", "2.0"}});
  EXPECT_TRUE(program.isCompute());
  EXPECT_EQ(program.localSize(), glm::uvec3(64, 1, 1));

  const std::vector<float> values = sampleValues(1000);  // not a multiple of 64: the tail group is partial
  gl::Buffer buffer = gl::Buffer::fromVector(values);
  buffer.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  program.setUniform("count", static_cast<unsigned>(values.size()));
  EXPECT_EQ(program.groupsFor(1000), glm::uvec3(16, 1, 1));
  program.dispatch(program.groupsFor(static_cast<std::uint32_t>(values.size())));
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

  const std::vector<float> doubled = buffer.download<float>(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(doubled[i], 2.0f * values[i]) << "index " << i;
}

TEST_F(GlLayer, CompileErrorInAnIncludeNamesThatFileAndLine) {
  const std::filesystem::path helper = testShader("broken_helper.glsl");
  const int line = lineOf(helper, "SYNTAX-ERROR-MARKER");
  ASSERT_GT(line, 0);
  try {
    gl::compileCompute(testShader("broken.comp"));
    FAIL() << "a shader with a syntax error compiled";
  } catch (const gl::ShaderError& e) {
    EXPECT_EQ(e.file(), "tests/glsl/broken_helper.glsl") << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find("tests/glsl/broken_helper.glsl:" + std::to_string(line)), std::string::npos)
        << e.what();
  }
}

TEST_F(GlLayer, MissingShaderFileIsAShaderError) {
  EXPECT_THROW(gl::compileCompute(testShader("no_such_shader.comp")), gl::ShaderError);
}

TEST_F(GlLayer, UnknownOrMistypedUniformThrows) {
  const gl::Program program = gl::compileCompute(testShader("double_values.comp"), {{"FACTOR", "2.0"}});
  EXPECT_TRUE(program.hasUniform("count"));
  EXPECT_FALSE(program.hasUniform("cuont"));
  EXPECT_THROW(program.setUniform("cuont", 3u), gl::GlError);
  EXPECT_NO_THROW(program.setUniformOptional("cuont", 3u));
  EXPECT_THROW(program.setUniform("count", 3), gl::GlError);     // int given, the shader has uint
  EXPECT_THROW(program.setUniform("count", 3.0f), gl::GlError);  // float given
  EXPECT_NO_THROW(program.setUniform("count", 3u));
}

TEST_F(GlLayer, DebugOutputTurnsARawGlErrorIntoAnException) {
  glBindBufferBase(GL_ARRAY_BUFFER, 0, 0);  // GL_INVALID_ENUM: not an indexed target
  EXPECT_THROW(gl::checkDebugErrors(), gl::GlError);
  EXPECT_TRUE(gl::takeDebugErrors().empty());  // the exception took them
}

TEST_F(GlLayer, GraphicsProgramFillsAFramebufferWithItsColor) {
  const gl::Program program = gl::compileGraphics(testShader("solid_color.vert"), testShader("solid_color.frag"));
  EXPECT_FALSE(program.isCompute());
  EXPECT_THROW(program.localSize(), gl::GlError);
  const gl::VertexArray vao = gl::VertexArray::create();
  for (int samples : {1, 4}) {
    const gl::Framebuffer target = gl::Framebuffer::createColorDepth(17, 9, samples);
    target.bind();
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    program.setUniform("color", glm::vec4(1.0f, 0.0f, 1.0f, 1.0f));
    program.use();
    vao.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    const std::vector<std::uint8_t> pixels = target.readPixelsRGBA();
    ASSERT_EQ(pixels.size(), 17u * 9u * 4u);
    for (std::size_t i = 0; i < pixels.size(); i += 4) {
      ASSERT_EQ(pixels[i + 0], 255) << "samples " << samples << " pixel " << i / 4;
      ASSERT_EQ(pixels[i + 1], 0) << "samples " << samples << " pixel " << i / 4;
      ASSERT_EQ(pixels[i + 2], 255) << "samples " << samples << " pixel " << i / 4;
      ASSERT_EQ(pixels[i + 3], 255) << "samples " << samples << " pixel " << i / 4;
    }
  }
  gl::Framebuffer::bindDefault();
}

TEST_F(GlLayer, ReadPixelsReturnsRowsTopToBottom) {
  const gl::Framebuffer target = gl::Framebuffer::createColorDepth(4, 6);
  target.bind();
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, 4, 1);  // GL's bottom row
  glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  const std::vector<std::uint8_t> pixels = target.readPixelsRGBA();
  EXPECT_EQ(pixels[0], 0);  // image top row: blue
  EXPECT_EQ(pixels[2], 255);
  EXPECT_EQ(pixels[(5 * 4) * 4 + 0], 255);  // image bottom row: red
  EXPECT_EQ(pixels[(5 * 4) * 4 + 2], 0);
  gl::Framebuffer::bindDefault();
}

TEST_F(GlLayer, TexturesUploadMipmapAndCubeFaces) {
  const int size = 8;
  std::vector<std::uint8_t> texels(size * size * 4);
  for (std::size_t i = 0; i < texels.size(); ++i)
    texels[i] = static_cast<std::uint8_t>(i % 251);
  gl::Texture texture = gl::Texture::create2D(size, size, GL_RGBA8, gl::Texture::fullMipLevels(size, size));
  EXPECT_EQ(texture.levels(), 4);
  texture.upload2D(GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  texture.generateMipmaps();
  texture.setSampling(GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
  texture.bind(0);
  std::vector<std::uint8_t> back(texels.size());
  glGetTextureImage(texture.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(back.size()), back.data());
  EXPECT_EQ(back, texels);

  gl::Texture cube = gl::Texture::createCube(4, GL_RGBA8);
  for (int face = 0; face < 6; ++face) {
    const std::vector<std::uint8_t> face_texels(4 * 4 * 4, static_cast<std::uint8_t>(40 * face));
    cube.uploadCubeFace(face, GL_RGBA, GL_UNSIGNED_BYTE, face_texels.data());
  }
  std::vector<std::uint8_t> faces(6 * 4 * 4 * 4);
  glGetTextureImage(cube.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(faces.size()), faces.data());
  for (int face = 0; face < 6; ++face)
    EXPECT_EQ(faces[static_cast<std::size_t>(face) * 64], 40 * face) << face;
  EXPECT_THROW(cube.uploadCubeFace(6, GL_RGBA, GL_UNSIGNED_BYTE, faces.data()), gl::GlError);
}

TEST_F(GlLayer, TimerQueryProbeAnswersWithoutCrashing) {
  const bool works = gl::timerQueriesWork();
  std::printf("GL_TIME_ELAPSED %s on %s\n", works ? "measures dispatches" : "does not measure dispatches",
              info().renderer.c_str());
  if (!works) return;  // callers fall back to the wall clock around glFinish
  const gl::Program program = gl::compileCompute(testShader("double_values.comp"), {{"FACTOR", "2.0"}});
  gl::Buffer buffer = gl::Buffer::fromVector(sampleValues(1 << 16));
  buffer.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  program.setUniform("count", 1u << 16);
  const gl::Query query = gl::Query::create();
  query.begin();
  program.dispatch(program.groupsFor(1u << 16));
  query.end();
  EXPECT_GT(query.result(), 0u);
}

}  // namespace
}  // namespace drape
